#include "simulate/imaging.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "basis/error.h"
#include "brdf/material_spec.h"
#include "tests/rig/rig_test_util.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

Pattern Uniform(const Rig& rig, uint16_t level) {
  Pattern p;
  p.width = rig.projector.lens.width;
  p.height = rig.projector.lens.height;
  p.bit_depth = rig.projector.bit_depth;
  p.levels.assign(static_cast<size_t>(p.width) * p.height, level);
  return p;
}

// A pattern like a zonal basis lobe of order ~6: (1 + cos(6 theta) cos(2 phi)) / 2 over the
// incident directions of the projector map.
Pattern BasisLike(const Rig& rig, const DirectionMap& projector) {
  Pattern p = Uniform(rig, 0);
  for (int i = 0; i < projector.size(); ++i) {
    if (!projector.Valid(i)) continue;
    const Vec3 w = projector.Direction(i);
    const double v = 0.5 * (1 + std::cos(6 * SphericalTheta(w)) * std::cos(2 * SphericalPhi(w)));
    p.levels[i] = static_cast<uint16_t>(std::lround(255 * v));
  }
  return p;
}

TEST(ImagingTest, LambertianUnderWhiteMatchesTheClosedForm) {
  // albedo / pi x irradiance x camera constant: the irradiance of uniform radiance L over the
  // zone [a, b] is L pi (sin^2 b - sin^2 a), and L is the projector's peak times the path
  // transmission. The simulator samples the lit zone cosine-weighted, which integrates a
  // Lambertian exactly; what is left is float rounding. 0.5% is the acceptance bound.
  const auto& shared = testing::SharedFastThesisRig();
  const auto material = MakeBrdf("lambert:0.18");
  const ForwardModel model(shared.optics, shared.maps, *material);
  const std::vector<float> rate = model.ElectronRate(Uniform(shared.rig, 255));
  const DomeDesign& d = shared.optics.design();
  const double irradiance = shared.rig.projector.peak_radiance_w_m2_sr *
                            model.ProjectorPathTransmission() * M_PI *
                            (std::pow(std::sin(d.zone_max_rad), 2) - std::pow(std::sin(d.zone_min_rad), 2));
  int checked = 0;
  double worst = 0;
  const int w = shared.rig.camera.width, h = shared.rig.camera.height;
  for (size_t i = 0; i < rate.size(); ++i) {
    // Pixels whose whole neighbourhood lands on the sample: their own aperture rays do too
    // (the map's 16 rays and the frame's differ, and at the rim of the image that matters).
    const int x = static_cast<int>(i) % w, y = static_cast<int>(i) / w;
    if (x == 0 || y == 0 || x == w - 1 || y == h - 1) continue;
    bool interior = true;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        interior = interior && shared.maps.camera.throughput[(y + dy) * w + x + dx] == 1.0f;
      }
    }
    if (!interior) continue;
    const double expected = model.CameraConstant(static_cast<int>(i)) * 0.18 / M_PI * irradiance;
    worst = std::max(worst, std::abs(rate[i] / expected - 1));
    ++checked;
  }
  EXPECT_GT(checked, 10000);
  EXPECT_LE(worst, 0.005);
}

// A Lambertian material seen only through Eval and its sampler, as any other material: the
// transport's general path (control variate fitted at probes plus MIS samples of the residual).
class SampledOnly final : public Brdf {
 public:
  explicit SampledOnly(std::unique_ptr<Brdf> inner) : inner_(std::move(inner)) {}
  Rgb Eval(const Vec3& w_i, const Vec3& w_o) const override { return inner_->Eval(w_i, w_o); }
  BrdfSample Sample(const Vec3& w_o, double u_lobe, double u0, double u1) const override {
    return inner_->Sample(w_o, u_lobe, u0, u1);
  }
  double Pdf(const Vec3& w_o, const Vec3& w_i) const override { return inner_->Pdf(w_o, w_i); }
  bool IsReciprocal() const override { return true; }
  bool IsEnergyConserving() const override { return true; }
  std::string Spec() const override { return "sampled-only:" + inner_->Spec(); }

 private:
  std::unique_ptr<Brdf> inner_;
};

TEST(ImagingTest, ALambertianIsIntegratedByItsControlVariateAloneAsTheSamplesWouldDoIt) {
  // A material whose f_r is the same everywhere (Brdf::ConstantValue) has no residual for the
  // samples to integrate: its transport holds no entries, only the control variate. The
  // general path, which fits the control variate and samples what is left, must give the same
  // frames: its residual is rounding (the fit's 1e-9 ridge), its storage float (1e-7).
  const auto& shared = testing::SharedFastThesisRig();
  ForwardModelOptions options;
  options.row_stride = 4;  // a quarter of the rows: enough pixels, 4x faster
  const auto material = MakeBrdf("lambert:albedo=0.5,0.3,0.2");
  ASSERT_TRUE(material->ConstantValue().has_value());
  const SampledOnly sampled_material(MakeBrdf("lambert:albedo=0.5,0.3,0.2"));
  ASSERT_FALSE(sampled_material.ConstantValue().has_value());
  const ForwardModel exact(shared.optics, shared.maps, *material, options);
  const ForwardModel sampled(shared.optics, shared.maps, sampled_material, options);
  EXPECT_EQ(exact.transport_entries(), 0u);
  EXPECT_GT(sampled.transport_entries(), 100000u);
  for (const Pattern& pattern :
       {Uniform(shared.rig, 255), BasisLike(shared.rig, shared.maps.projector)}) {
    const std::vector<float> a = exact.ElectronRate(pattern), b = sampled.ElectronRate(pattern);
    ASSERT_EQ(a.size(), b.size());
    const double peak = *std::max_element(b.begin(), b.end());
    ASSERT_GT(peak, 0);
    int checked = 0;
    double worst = 0;
    for (size_t i = 0; i < a.size(); ++i) {
      if (b[i] < 0.01 * peak) continue;  // unlit pixels and skipped rows: both 0
      worst = std::max(worst, std::abs(a[i] / b[i] - 1.0));
      ++checked;
    }
    EXPECT_GT(checked, 2000);
    EXPECT_LE(worst, 1e-5);
  }
}

TEST(ImagingTest, SignalIsLinearInExposureAndNoiseFreeFramesAreExact) {
  const auto& shared = testing::SharedFastThesisRig();
  const auto material = MakeBrdf("lambert:0.5");
  const ForwardModel model(shared.optics, shared.maps, *material);
  const Pattern white = Uniform(shared.rig, 255);
  const std::vector<float> rate = model.ElectronRate(white);
  const SensorParams& s = shared.rig.sensor;
  // The brightest pixel at 60% of the full well in the longer exposure.
  const double exposure_us = 0.6 * s.full_well_e / *std::max_element(rate.begin(), rate.end()) * 1e6;
  const Frame full = model.RenderFromRate(rate, exposure_us, 1, false);
  const Frame half = model.RenderFromRate(rate, exposure_us / 2, 1, false);
  double sum_full = 0, sum_half = 0;
  for (size_t i = 0; i < rate.size(); ++i) {
    // Noise off: DN = round(black + rate t / gain), below saturation.
    const double expected = s.dark_level_dn + rate[i] * full.exposure_us * 1e-6 / s.gain_e_per_dn;
    if (expected < s.saturation_dn - 1) {
      EXPECT_NEAR(full.data[i], expected, 0.5 + 1e-9);
    }
    sum_full += full.data[i] - s.dark_level_dn;
    sum_half += half.data[i] - s.dark_level_dn;
  }
  // Half the exposure, half the signal (rounding averages out over ~17000 pixels).
  EXPECT_NEAR(sum_half / sum_full, 0.5, 1e-3);
  EXPECT_EQ(full.width, shared.rig.camera.width);
  EXPECT_EQ(full.layout, PixelLayout::kBayerRGGB);
  EXPECT_EQ(full.bit_depth, 12);
}

TEST(ImagingTest, NoiseVarianceFollowsTheSensorModel) {
  // Two frames with different noise keys: var(A - B) / 2 per pixel against
  // (electrons + read^2) / gain^2 + 1/12 (quantization), summed over unsaturated pixels. Over
  // ~17000 pixels the ratio's standard error is ~1%; the acceptance bound is 5%.
  const auto& shared = testing::SharedFastThesisRig();
  const auto material = MakeBrdf("lambert:0.18");
  const ForwardModel model(shared.optics, shared.maps, *material);
  const std::vector<float> rate = model.ElectronRate(Uniform(shared.rig, 128));
  const SensorParams& s = shared.rig.sensor;
  // An exposure that puts the brightest pixel at 70% of the full well.
  const double exposure_us = 0.7 * s.full_well_e / *std::max_element(rate.begin(), rate.end()) * 1e6;
  const Frame a = model.RenderFromRate(rate, exposure_us, 11, true);
  const Frame b = model.RenderFromRate(rate, exposure_us, 12, true);
  double observed = 0, predicted = 0, mean_electrons = 0;
  int n = 0;
  for (size_t i = 0; i < rate.size(); ++i) {
    const double e = rate[i] * exposure_us * 1e-6;
    if (e < 100 || e > 0.8 * s.full_well_e) continue;
    const double d = static_cast<double>(a.data[i]) - b.data[i];
    observed += 0.5 * d * d;
    predicted += (e + s.read_noise_e * s.read_noise_e) / (s.gain_e_per_dn * s.gain_e_per_dn) + 1.0 / 12;
    mean_electrons += e;
    ++n;
  }
  ASSERT_GT(n, 5000);
  EXPECT_NEAR(observed / predicted, 1.0, 0.05) << "mean signal " << mean_electrons / n << " e-";
  // Deterministic: the same key gives the same frame, another key another one.
  EXPECT_EQ(model.RenderFromRate(rate, exposure_us, 11, true).data, a.data);
  EXPECT_NE(a.data, b.data);
}

TEST(ImagingTest, SaturationClipsAtTheSensorMaximum) {
  const auto& shared = testing::SharedFastThesisRig();
  const auto material = MakeBrdf("lambert:0.9");
  const ForwardModel model(shared.optics, shared.maps, *material);
  const Frame frame = model.Render(Uniform(shared.rig, 255), 5e6, 3, true);
  int saturated = 0;
  for (size_t i = 0; i < frame.data.size(); ++i) {
    EXPECT_LE(frame.data[i], shared.rig.sensor.saturation_dn);
    if (shared.maps.camera.throughput[i] == 1.0f) saturated += frame.data[i] == 4095 || frame.data[i] >= 64 + 10000 / 2.5 - 40;
  }
  EXPECT_GT(saturated, 10000);
  // A fractional saturation level (the rig file allows one) clips to the count below it.
  Rig rig = shared.rig;
  rig.sensor.saturation_dn = 4001.5;
  const OpticalSystem optics(rig);
  const ForwardModel clipped(optics, shared.maps, *material);
  const Frame at_level = clipped.Render(Uniform(rig, 255), 5e6, 3, true);
  EXPECT_EQ(*std::max_element(at_level.data.begin(), at_level.data.end()), 4001);
  EXPECT_GT(std::count(at_level.data.begin(), at_level.data.end(), 4001), 10000);
}

// Frames at the default sample count against a 16x reference on every 12th row (same seed
// family, independent points): relative RMS over valid pixels per pattern (acceptance: 1%). The
// two transports are built once and render every pattern. Both integrate the compared rows only:
// a pixel's samples depend on the seed and the pixel, not on which other rows are integrated.
std::vector<double> ConvergenceErrors(const std::string& spec, const std::vector<Pattern>& patterns) {
  const auto& shared = testing::SharedFastThesisRig();
  const auto material = MakeBrdf(spec);
  ForwardModelOptions options;
  options.seed = 5;
  options.row_stride = 12;
  const ForwardModel model(shared.optics, shared.maps, *material, options);
  Rig reference_rig = shared.rig;
  reference_rig.simulation.samples_per_pixel *= 16;
  const OpticalSystem reference_optics(reference_rig);
  options.seed = 6;
  const ForwardModel reference(reference_optics, shared.maps, *material, options);
  std::vector<double> errors;
  for (const Pattern& pattern : patterns) {
    const std::vector<float> a = model.ElectronRate(pattern), b = reference.ElectronRate(pattern);
    double num = 0, den = 0;
    for (size_t i = 0; i < a.size(); ++i) {
      const int y = static_cast<int>(i) / shared.rig.camera.width;
      if (y % 12 != 0 || !shared.maps.camera.Valid(static_cast<int>(i))) continue;
      num += (a[i] - b[i]) * (a[i] - b[i]);
      den += b[i] * b[i];
    }
    errors.push_back(std::sqrt(num / den));
  }
  return errors;
}

TEST(ImagingTest, FramesConvergeForSharpMaterials) {
  const auto& shared = testing::SharedFastThesisRig();
  const std::vector<Pattern> patterns = {Uniform(shared.rig, 255),
                                         BasisLike(shared.rig, shared.maps.projector)};
  for (const char* spec : {"merl:blue-acrylic", "ggx:alpha=0.05,F0=0.04,kd=0.1"}) {
    const std::vector<double> errors = ConvergenceErrors(spec, patterns);
    EXPECT_LE(errors[0], 0.01) << spec << " white";
    EXPECT_LE(errors[1], 0.01) << spec << " basis-like";
  }
}

// The diagnostic split of the transport by sampling strategy (ForwardModelOptions::strategies):
// the samples are drawn and weighted the same way whatever is kept, so per pixel the zone part
// plus the lobe part is the whole plus the control variate's exact part (in each of the four).
// What separates them is the 16-bit packing of each pixel's entries (at most 1.5e-5 of the
// pixel's largest entry per entry): 1e-4 of the frame, relative RMS, bounds it with margin.
TEST(ImagingTest, TheStrategiesSplitAddsUpToTheWholeTransport) {
  const auto& shared = testing::SharedFastThesisRig();
  const auto material = MakeBrdf("merl:blue-acrylic");
  using Strategies = ForwardModelOptions::Strategies;
  const std::vector<Pattern> patterns = {Uniform(shared.rig, 255),
                                         BasisLike(shared.rig, shared.maps.projector)};
  std::vector<std::vector<std::vector<float>>> rates;  // [strategy][pattern]
  std::vector<ForwardModel::SampleCounts> counts;
  for (Strategies s : {Strategies::kBoth, Strategies::kZoneOnly, Strategies::kLobeOnly,
                       Strategies::kControlOnly}) {
    ForwardModelOptions options;
    options.row_stride = 12;
    options.strategies = s;
    const ForwardModel model(shared.optics, shared.maps, *material, options);
    EXPECT_FALSE(model.from_cache());
    rates.push_back({});
    for (const Pattern& p : patterns) rates.back().push_back(model.ElectronRate(p));
    counts.push_back(model.sample_counts());
  }
  for (size_t k = 0; k < patterns.size(); ++k) {
    const auto &both = rates[0][k], &zone = rates[1][k], &lobe = rates[2][k],
               &control = rates[3][k];
    double num = 0, den = 0, lobe_part = 0;
    for (size_t i = 0; i < both.size(); ++i) {
      const double d = double(zone[i]) + lobe[i] - control[i] - both[i];
      num += d * d;
      den += double(both[i]) * both[i];
      lobe_part += (double(lobe[i]) - control[i]) * (double(lobe[i]) - control[i]);
    }
    ASSERT_GT(den, 0);
    EXPECT_LT(std::sqrt(num / den), 1e-4) << "pattern " << k;
    // Neither part is trivially zero: the split separates something.
    EXPECT_GT(std::sqrt(lobe_part / den), 0.01) << "pattern " << k;
  }
  // The same samples are drawn whatever is kept.
  for (const auto& c : counts) EXPECT_TRUE(c == counts[0]);
  // Blue-acrylic's glossy samples are lost partly below the horizon and partly outside the lit
  // zone (measured: 20% and 29% of the draws), and a draw always gives a direction.
  const ForwardModel::SampleCounts& c = counts[0];
  EXPECT_GT(c.zone, 0);
  EXPECT_GT(c.lobe, 0);
  EXPECT_EQ(c.lobe_no_sample, 0);
  EXPECT_GT(c.lobe_below_horizon, c.lobe / 10);
  EXPECT_GT(c.lobe_unlit, c.lobe / 10);
  EXPECT_LT(c.lobe_below_horizon + c.lobe_unlit, c.lobe);
}

TEST(ImagingTest, FlatMirrorShowsTheProjectorPixelAlongTheMirrorPath) {
  // With a mirror as the sample, a camera pixel sees the projector pixel at the end of its
  // reflected path. Pattern: each projector pixel's level encodes its column; the frame
  // (noise off) then shows the column, which is checked against the path traced here.
  const auto& shared = testing::SharedFastThesisRig();
  const auto mirror = MakeBrdf("mirror:R=1");
  const ForwardModel model(shared.optics, shared.maps, *mirror);
  Pattern columns = Uniform(shared.rig, 0);
  for (int y = 0; y < columns.height; ++y) {
    for (int x = 0; x < columns.width; ++x) columns.levels[y * columns.width + x] = x;
  }
  Rig rig = shared.rig;
  const std::vector<float> lit = model.ElectronRate(Uniform(rig, 255));
  const std::vector<float> coded = model.ElectronRate(columns);
  int checked = 0, agree = 0;
  for (int y = 0; y < rig.camera.height; y += 3) {
    for (int x = 0; x < rig.camera.width; x += 3) {
      const int i = y * rig.camera.width + x;
      if (shared.maps.camera.throughput[i] < 1.0f || lit[i] <= 0) continue;
      const double column = 255.0 * coded[i] / lit[i];
      const auto path = shared.optics.TraceToSample(shared.optics.camera().ChiefRay(x + 0.5, y + 0.5));
      if (path.status != OpticalSystem::PathStatus::kLanded) continue;
      const Vec3 reflected{-path.w.x, -path.w.y, path.w.z};
      const auto back = shared.optics.TraceFromSample(path.landing_point, reflected);
      if (!back.reached) continue;
      const auto proj = shared.optics.projector().Project(back.at_lens);
      ++checked;
      // The pixel averages over its footprint and aperture: within a projector pixel or two.
      if (std::abs(column - proj.px) < 2.0) ++agree;
    }
  }
  EXPECT_GT(checked, 500);
  EXPECT_GT(agree, checked * 95 / 100);
}

TEST(ImagingTest, PatternsRenderedTogetherGiveEachPatternsRateBitForBit) {
  // Eleven patterns (a pass of eight and a pass of three), rendered together and one by one:
  // the same floats, so a virtual session's frames do not depend on what it was told ahead.
  const auto& shared = testing::SharedFastThesisRig();
  const auto material = MakeBrdf("ggx:alpha=0.2,F0=0.04,kd=0.2");
  ForwardModelOptions options;
  options.row_stride = 3;  // a third of the rows: the same rows, at a third of the cost
  const ForwardModel model(shared.optics, shared.maps, *material, options);
  ASSERT_GT(model.transport_entries(), 100000u);
  std::vector<Pattern> patterns = {Uniform(shared.rig, 255),
                                   BasisLike(shared.rig, shared.maps.projector)};
  uint64_t state = 77;
  while (patterns.size() < 11) {
    Pattern p = Uniform(shared.rig, 0);
    for (uint16_t& level : p.levels) level = static_cast<uint16_t>((state = HashMix(state)) % 256);
    patterns.push_back(std::move(p));
  }
  const std::vector<std::vector<float>> together = model.ElectronRates(patterns);
  ASSERT_EQ(together.size(), patterns.size());
  for (size_t i = 0; i < patterns.size(); ++i) {
    EXPECT_EQ(together[i], model.ElectronRate(patterns[i])) << "pattern " << i;
  }
  // A pattern that does not fit is named by its place.
  patterns[9].bit_depth = 10;
  try {
    model.ElectronRates(patterns);
    ADD_FAILURE() << "a 10-bit pattern for an 8-bit projector was rendered";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("pattern 10 of 11"), std::string::npos) << e.what();
  }
}

TEST(ImagingTest, RejectsPatternsOfTheWrongShape) {
  const auto& shared = testing::SharedFastThesisRig();
  const auto material = MakeBrdf("lambert:0.5");
  const ForwardModel model(shared.optics, shared.maps, *material);
  Pattern p = Uniform(shared.rig, 10);
  p.width -= 1;
  EXPECT_THROW(model.ElectronRate(p), InputError);
  p = Uniform(shared.rig, 10);
  p.bit_depth = 10;
  EXPECT_THROW(model.ElectronRate(p), InputError);
  p = Uniform(shared.rig, 300);
  EXPECT_THROW(model.ElectronRate(p), InputError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
