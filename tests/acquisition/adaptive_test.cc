// Adaptive capture (acquisition/adaptive.h): the stopping rule, the band energies and their
// isotropy residual, the exposure rule and plan truncation against closed forms; then adaptive
// sessions on the simulated thesis rig (fast preset, seed 1): a Lambertian stops at band 1 in less
// rig time than the thesis's bracket; a glossy isotropic material keeps its bands, skips the lobes
// isotropy makes redundant at no cost in accuracy, resumes after an interruption to the same
// result and re-processes identically.
#include "acquisition/adaptive.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <filesystem>

#include "acquisition/capture_job.h"
#include "acquisition/ground_truth.h"
#include "basis/error.h"
#include "basis/spherical_harmonics.h"
#include "brdf/material_spec.h"
#include "simulate/virtual_rig.h"
#include "tests/acquisition/acquisition_test_util.h"
#include "tests/rig/rig_test_util.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

namespace fs = std::filesystem;

AdaptiveBand Band(int l, double energy, double floor) {
  AdaptiveBand b;
  b.l = l;
  b.energy = energy;
  b.noise = floor;
  b.floor = floor;
  return b;
}

// Geometric decay E_l = 4^-l over a flat floor 1e-4: S_l > F_l up to l = 6 (4^-6 = 2.4e-4 >
// 2e-4), and band 7 (6.1e-5 < 2e-4) is dropped.
TEST(Adaptive, StopsAtTheFirstBandBelowItsFloorAndDropsIt) {
  AdaptiveOptions o;
  std::vector<AdaptiveBand> bands;
  AdaptiveDecision d;
  for (int l = 0; l <= 10 && !d.stop; ++l) {
    bands.push_back(Band(l, std::pow(4.0, -l) + 1e-4, 1e-4));
    d = DecideAfterBand(bands, o);
  }
  ASSERT_TRUE(d.stop);
  EXPECT_EQ(bands.back().l, 7);
  EXPECT_EQ(d.order, 6);
  EXPECT_EQ(d.reason, "noise floor");
  // Predicted error: sqrt((sum of the kept floors + band 7's signal) / kept signal).
  double s = 0;
  for (int l = 0; l <= 6; ++l) s += std::pow(4.0, -l);
  EXPECT_NEAR(d.predicted_error, std::sqrt((7e-4 + std::pow(4.0, -7)) / s), 1e-12);
  // min_order protects the first bands even when they are below the floor.
  o.min_order = 2;
  EXPECT_FALSE(DecideAfterBand({Band(0, 1, 0), Band(1, 0, 1), Band(2, 1e-9, 1)}, o).stop);
  const AdaptiveDecision low = DecideAfterBand({Band(0, 1, 0), Band(1, 0, 1)}, o);
  EXPECT_FALSE(low.stop);
}

TEST(Adaptive, ErrorTargetUsesTheGeometricTail) {
  // E = 1, 0.1, 0.01 with no floor: q = 0.1, tail = 0.01 * 0.1 / 0.9, error = sqrt(tail / 1.11).
  AdaptiveOptions o;
  o.error_target = 0.04;
  const std::vector<AdaptiveBand> bands = {Band(0, 1, 0), Band(1, 0.1, 0), Band(2, 0.01, 0)};
  const AdaptiveDecision d = DecideAfterBand(bands, o);
  const double expected = std::sqrt((0.01 * 0.1 / 0.9) / 1.11);
  EXPECT_NEAR(d.predicted_error, expected, 1e-12);  // 0.0316
  EXPECT_TRUE(d.stop);
  EXPECT_EQ(d.order, 2);
  EXPECT_EQ(d.reason, "error target");
  o.error_target = 0.03;
  EXPECT_FALSE(DecideAfterBand(bands, o).stop);
}

// A grid of z_lm = a(theta) cos(m phi) (m >= 0) or sin(|m| phi): energy sum_rows Omega a^2 n/2
// (n/1 for m = 0) and no off-harmonic part; adding b sin(m phi) to a cos function adds b^2 n/2
// Omega to both the energy and the off-harmonic part (the sampled harmonics are orthogonal).
TEST(Adaptive, BandEnergyAndIsotropyResidual) {
  const ExitantGrid grid = MakeExitantGrid(Zone::FromDegrees(10, 50), 2.0, 4.0);
  const int l = 2, n = grid.n_phi;
  std::vector<GridImage> images(2 * l + 1);
  double expected = 0, expected_off = 0;
  for (int f = 0; f < 2 * l + 1; ++f) {
    const int m = f - l;
    for (int ch = 0; ch < 3; ++ch) {
      images[f].value[ch].assign(grid.cells(), 0.0f);
      images[f].variance[ch].assign(grid.cells(), 1e-6f);
      for (int i = 0; i < grid.n_theta; ++i) {
        const double a = 0.5 + 0.1 * i + 0.05 * ch;
        const double b = m == 1 ? 0.2 : 0.0;  // an anisotropic part on Z_2,1
        for (int j = 0; j < n; ++j) {
          const double phi = (j + 0.5) * grid.phi_step_rad;
          const double h = m > 0 ? std::cos(m * phi) : m < 0 ? std::sin(-m * phi) : 1.0;
          images[f].value[ch][i * n + j] = static_cast<float>(a * h + b * std::sin(m * phi));
        }
        const double omega = grid.CellSolidAngle(i);
        expected += omega * a * a * (m == 0 ? n : n / 2.0) + omega * b * b * n / 2.0;
        expected_off += omega * b * b * n / 2.0;
      }
    }
  }
  std::vector<const GridImage*> ptrs;
  for (const GridImage& g : images) ptrs.push_back(&g);
  const AdaptiveBand band = MeasureBandEnergy(l, ptrs, grid);
  // Float storage of the values: relative 1e-6.
  EXPECT_NEAR(band.energy, expected, 2e-6 * expected);
  EXPECT_NEAR(band.off_harmonic, expected_off, 2e-6 * expected);
  double noise = 0;
  for (int i = 0; i < grid.n_theta; ++i) noise += 3 * 5 * grid.CellSolidAngle(i) * n * 1e-6;
  EXPECT_NEAR(band.noise, noise, 1e-6 * noise);
  EXPECT_EQ(band.floor, band.noise);
}

TEST(Adaptive, FloorProfileIsTheLeakageRatio) {
  const std::vector<double> p =
      FloorProfile({Band(0, 1, 0), Band(1, 0.5, 0), Band(2, 0.003, 0), Band(3, 0.0015, 0)});
  ASSERT_EQ(p.size(), 4u);
  EXPECT_EQ(p[0], 0);
  EXPECT_EQ(p[1], 0);
  EXPECT_DOUBLE_EQ(p[2], 0.003 / 1.5);
  EXPECT_DOUBLE_EQ(p[3], 0.0015 / 1.503);
}

TEST(Adaptive, SecondExposureKeepsTheQuantileInRange) {
  RigCalibration c;
  c.black_dn = 100;
  c.saturation_dn = 4095;
  c.camera_response.assign(1000, 1);  // every pixel valid
  Frame f;
  f.width = 100;
  f.height = 10;
  f.exposure_us = 1000;
  f.data.assign(1000, 100);
  // Signal 0..999 DN above black.
  for (int i = 0; i < 1000; ++i) f.data[i] = static_cast<uint16_t>(100 + i);
  AdaptiveOptions o;
  // Quantile index floor(0.995 * 999) = 994 -> 994 DN; ratio 0.9 * 3995 / 994 = 3.617.
  EXPECT_NEAR(AdaptiveExposureUs(f, c, o), 1000 * 0.9 * 3995 / 994, 1e-6);
  // A dark pattern gets the longest exposure; a bright one never less than the first.
  f.data.assign(1000, 100);
  EXPECT_DOUBLE_EQ(AdaptiveExposureUs(f, c, o), 16000);
  f.data.assign(1000, 4000);
  EXPECT_DOUBLE_EQ(AdaptiveExposureUs(f, c, o), 1000);
}

TEST(Adaptive, TruncatedPlanKeepsFrameIndices) {
  const CapturePlan plan = MakePlan({DegToRad(10), DegToRad(50), 4, 2, 4, 1000, 1});
  const CapturePlan kept = TruncatePlan(plan, 2);
  EXPECT_EQ(kept.order, 2);
  EXPECT_EQ(kept.lobes.size(), 1u + 1u + 2u * 8u);
  for (int i = 0; i < kept.frame_count(); ++i) {
    const PlannedFrame a = kept.Frame(i), b = plan.Frame(i);
    EXPECT_EQ(kept.lobes[a.lobe].Name(), plan.lobes[b.lobe].Name());
    EXPECT_EQ(a.exposure, b.exposure);
  }
  EXPECT_THROW(TruncatePlan(plan, 5), InputError);
  AdaptiveOptions bad;
  bad.target_level = 0.99;
  EXPECT_THROW(bad.Validate(), InputError);
  EXPECT_THROW(AdaptiveOptions::FromJson({{"noise_ratio", -1}}), InputError);
  const AdaptiveOptions round = AdaptiveOptions::FromJson(AdaptiveOptions().ToJson());
  EXPECT_EQ(round.ToJson(), AdaptiveOptions().ToJson());
}

using Rigged = testing::SimulatedRig;

std::string TempDir(const std::string& name) { return testing::FreshTempDir("adaptive-test", name); }

CaptureJobOptions Job(const std::string& dir, int order, bool adaptive) {
  CaptureJobOptions o;
  o.processing.write_hdr_images = false;
  o.out_dir = dir;
  o.order = order;
  o.adaptive.enabled = adaptive;
  return o;
}

// A Lambertian's f cos(theta_i) is linear in cos(theta_i), so only bands 0 and 1 carry signal:
// the capture must stop after band 2 and drop it. Its error (order 4, the missing bands counted as
// zero) must stay within the fixed capture's: both are ~1% (noise, seed 1).
TEST(AdaptiveCapture, LambertianStopsAfterBandOneInLessTime) {
  Rigged setup("lambertian:0.18");
  double fixed_s = 0, adaptive_s = 0;
  const std::string fixed_dir = TempDir("lambert-fixed"), dir = TempDir("lambert-adaptive");
  const CaptureJobResult fixed = setup.Run(Job(fixed_dir, 4, false), &fixed_s);
  const CaptureJobResult r = setup.Run(Job(dir, 4, true), &adaptive_s);
  ASSERT_TRUE(fixed.complete && r.complete);
  EXPECT_EQ(r.zonal.order, 1) << r.adaptive.dump();
  EXPECT_EQ(r.adaptive["reason"], "noise floor");
  EXPECT_TRUE(r.adaptive["isotropic"].get<bool>());
  EXPECT_LT(adaptive_s, 0.3 * fixed_s);  // 8 of 50 patterns + band 2, 2 short frames each
  const GroundTruth truth = TrueZonalCoefficients(*MakeBrdf("lambertian:0.18"), fixed.zonal);
  const double e_fixed = CoefficientError(fixed.zonal, truth);
  // Padded: the truth of bands 2..4 is zero, so only bands 0..1 add error; CoefficientError
  // compares the functions both have, and the truth's norm is all in bands 0..1.
  const double e_adaptive = CoefficientError(r.zonal, truth);
  EXPECT_LE(e_adaptive, e_fixed * 1.5 + 0.002) << e_fixed;
  // session.json holds the truncated plan, and the session re-processes to the same data.
  const nlohmann::json s = SessionFolder::Open(dir).session();
  EXPECT_EQ(s["plan"]["order"], 1);
  EXPECT_EQ(s["adaptive"]["state"], "done");
  const ProcessResult again =
      ProcessSession(dir, setup.calibration, ProcessingOptions(), testing::TestCacheDir());
  ASSERT_EQ(again.zonal.order, 1);
  for (int ch = 0; ch < 3; ++ch) {
    EXPECT_LE((again.zonal.tensor[ch] - r.zonal.tensor[ch]).cwiseAbs().maxCoeff(),
              1e-6 * r.zonal.tensor[ch].cwiseAbs().maxCoeff());
  }
  fs::remove_all(fixed_dir);
  fs::remove_all(dir);
}

// Interrupted after 40 frames and resumed: the same decisions (they are made from the journaled
// frames) and the same coefficients as an uninterrupted run.
TEST(AdaptiveCapture, GlossyKeepsItsBandsAndResumesIdentically) {
  Rigged setup("ggx:alpha=0.25,F0=0.5,kd=0.2");
  const std::string whole = TempDir("glossy-whole"), parts = TempDir("glossy-parts");
  const auto& counters = static_cast<const VirtualCamera&>(setup.camera());
  const uint64_t ahead_before = counters.rates_rendered_ahead();
  const uint64_t shown_before = counters.rates_from_windows();
  const CaptureJobResult r = setup.Run(Job(whole, 3, true));
  ASSERT_TRUE(r.complete);
  EXPECT_EQ(r.zonal.order, 3) << r.adaptive.dump();
  // Isotropic: band l skips both lobes of Z_l,-m and the negative lobe of Z_l,m, m = 1..l: 3 l
  // lobes, 6 + 9 in bands 2 and 3.
  ASSERT_TRUE(r.adaptive["isotropic"].get<bool>());
  EXPECT_EQ(r.adaptive["skipped_lobes"].size(), 15u);
  // The virtual projector is told the patterns ahead but for lobes known to be skipped
  // (CaptureOptions::skip_lobe_ahead), so each pattern it rendered ahead was then shown (without
  // that: 24 rendered, 17 shown).
  EXPECT_GT(counters.rates_from_windows() - shown_before, 0u);
  EXPECT_EQ(counters.rates_rendered_ahead() - ahead_before,
            counters.rates_from_windows() - shown_before);
  // The synthesized functions are projections onto the one azimuthal harmonic isotropy allows,
  // which removes the error outside it: against the truth, no larger an error than a capture that
  // measures every lobe (measured 0.89% vs 1.36%, seed 1). The session re-processes to the same
  // coefficients.
  CaptureJobOptions all = Job(TempDir("glossy-all-lobes"), 3, true);
  all.adaptive.skip_isotropic = false;
  const CaptureJobResult measured = setup.Run(all);
  ASSERT_TRUE(measured.complete);
  const GroundTruth truth =
      TrueZonalCoefficients(*MakeBrdf("ggx:alpha=0.25,F0=0.5,kd=0.2"), r.zonal);
  const double e_skipped = CoefficientError(r.zonal, truth),
               e_measured = CoefficientError(measured.zonal, truth);
  RecordProperty("error_skipped_ppm", static_cast<int>(1e6 * e_skipped));
  RecordProperty("error_measured_ppm", static_cast<int>(1e6 * e_measured));
  EXPECT_LE(e_skipped, e_measured);
  const ProcessResult again =
      ProcessSession(whole, setup.calibration, ProcessingOptions(), testing::TestCacheDir());
  for (int ch = 0; ch < 3; ++ch) {
    EXPECT_LE((again.zonal.tensor[ch] - r.zonal.tensor[ch]).cwiseAbs().maxCoeff(),
              1e-6 * r.zonal.tensor[ch].cwiseAbs().maxCoeff());
  }
  fs::remove_all(all.out_dir);
  std::atomic<bool> stop{false};
  CaptureJobOptions first = Job(parts, 3, true);
  first.interrupt = &stop;
  first.progress = [&](const Progress& p) {
    if (p.stage == "capture" && p.done >= 40) stop = true;
  };
  EXPECT_FALSE(setup.Run(first).complete);
  CaptureJobOptions second = Job(parts, 3, false);  // adaptive comes from session.json
  second.resume = true;
  const CaptureJobResult resumed = setup.Run(second);
  ASSERT_TRUE(resumed.complete);
  EXPECT_EQ(resumed.zonal.order, r.zonal.order);
  EXPECT_GT(resumed.capture.frames_reused, 0);
  for (int ch = 0; ch < 3; ++ch) {
    EXPECT_LE((resumed.zonal.tensor[ch] - r.zonal.tensor[ch]).cwiseAbs().maxCoeff(),
              1e-6 * r.zonal.tensor[ch].cwiseAbs().maxCoeff());
  }
  fs::remove_all(whole);
  fs::remove_all(parts);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
