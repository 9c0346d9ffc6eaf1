#include "acquisition/zonal.h"

#include <cmath>
#include <filesystem>
#include <functional>
#include <fstream>
#include <random>

#include <gtest/gtest.h>

#include "acquisition/rig_calibration.h"
#include "basis/error.h"
#include "basis/quadrature.h"
#include "basis/spherical_harmonics.h"
#include "tests/rig/rig_test_util.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

namespace fs = std::filesystem;

std::string TempPath(const std::string& name) {
  std::string leaf = "zbrdf-zonal-test-";
  leaf += std::to_string(::getpid());
  leaf += "-";
  leaf += name;
  return (fs::temp_directory_path() / leaf).string();
}

const Zone kZone = Zone::FromDegrees(9.6, 56.5);

TEST(ExitantGrid, CellsTileTheZone) {
  const ExitantGrid g = MakeExitantGrid(kZone, 1.0, 2.0);
  EXPECT_EQ(g.n_theta, 47);  // 46.9 deg in 1 deg rows, the last one partial
  EXPECT_EQ(g.n_phi, 180);
  double total = 0;
  for (int i = 0; i < g.n_theta; ++i) total += g.CellSolidAngle(i) * g.n_phi;
  EXPECT_NEAR(total, kZone.solid_angle_sr(), 1e-12);
  for (int i = 0; i < g.n_theta; ++i) {
    for (int j = 0; j < g.n_phi; ++j) ASSERT_EQ(g.CellOf(g.CellCenter(i, j)), i * g.n_phi + j);
  }
  EXPECT_EQ(g.CellOf(Vec3{0, 0, 1}), -1);
  EXPECT_EQ(g.CellOf(Vec3{1, 0, 0}), -1);
}

TEST(ExitantGrid, AbsurdStepsAreRejected) {
  EXPECT_THROW(MakeExitantGrid(kZone, 0, 2), InputError);
  EXPECT_THROW(MakeExitantGrid(kZone, 1, 45), InputError);
  EXPECT_THROW(MakeExitantGrid(kZone, std::nan(""), 2), InputError);
  // A damaged file's tiny step (fuzz corpus regression-tiny-exitant-step.exr): no int overflow.
  EXPECT_THROW(MakeExitantGrid(kZone, 1e-20, 2), InputError);
  EXPECT_THROW(MakeExitantGrid(kZone, 1, 1e-20), InputError);
}

TEST(CellIntegrals, MatchAFinerQuadratureAndCellAveragingBlursLittle) {
  const ExitantGrid g = MakeExitantGrid(kZone, 1.0, 2.0);
  const ZonalBasis zb(kZone, 4);
  const Eigen::MatrixXd a = CellIntegrals(g, zb);
  // Independent reference: Gauss-Legendre (24 x 24) in the virtual sphere's polar angle
  // theta_v (cos theta = (a + b) / 2 + (b - a) / 2 cos theta_v), where every Z_lm is a smooth
  // trigonometric polynomial, so the rule converges to rounding.
  const GaussLegendreRule rule = GaussLegendre(24);
  const double lo = kZone.cos_lower(), hi = kZone.cos_upper();
  std::vector<double> z(zb.size());
  for (int cell : {0, 5, 17 * 180 + 33, 46 * 180 + 179}) {
    const int i = cell / g.n_phi, j = cell % g.n_phi;
    const auto virtual_angle = [&](double x) {
      return std::acos(std::clamp((2 * x - lo - hi) / (hi - lo), -1.0, 1.0));
    };
    const double v0 = virtual_angle(std::cos(g.ThetaLow(i))), v1 = virtual_angle(std::cos(g.ThetaHigh(i)));
    Eigen::VectorXd fine = Eigen::VectorXd::Zero(zb.size());
    for (int u = 0; u < 24; ++u) {
      const double v = 0.5 * (v0 + v1) + 0.5 * (v1 - v0) * rule.nodes[u];
      const double x = 0.5 * (lo + hi) + 0.5 * (hi - lo) * std::cos(v);
      const double dx = 0.5 * (hi - lo) * std::sin(v) * 0.5 * (v1 - v0) * rule.weights[u];
      for (int w = 0; w < 24; ++w) {
        const double phi = (j + 0.5 + 0.5 * rule.nodes[w]) * g.phi_step_rad;
        zb.Eval(x, phi, z.data());
        for (int k = 0; k < zb.size(); ++k) fine[k] += z[k] * dx * 0.5 * rule.weights[w] * g.phi_step_rad;
      }
    }
    EXPECT_LT((a.row(cell).transpose() - fine).cwiseAbs().maxCoeff(), 1e-10 * g.CellSolidAngle(i)) << cell;
  }
  // Z_00 is constant: its cell integrals are exactly Z_00 times the cell's solid angle.
  const double z00 = zb.normalization() / std::sqrt(4 * M_PI);
  for (int c = 0; c < g.cells(); c += 97) {
    EXPECT_NEAR(a(c, 0), z00 * g.CellSolidAngle(c / g.n_phi), 1e-14);
  }
  // The cell-averaged basis is nearly orthonormal (why ProjectExitant may invert its Gram):
  // the deficit is -|(I - P) Z_k|^2, largest for Z_l0 near the zone's edges.
  Eigen::VectorXd inv_area(g.cells());
  for (int c = 0; c < g.cells(); ++c) inv_area[c] = 1 / g.CellSolidAngle(c / g.n_phi);
  const Eigen::MatrixXd gram = a.transpose() * inv_area.asDiagonal() * a;
  const Eigen::MatrixXd deficit = Eigen::MatrixXd::Identity(zb.size(), zb.size()) - gram;
  EXPECT_LT(deficit.cwiseAbs().maxCoeff(), 0.02);
  EXPECT_GT(deficit.diagonal().minCoeff(), -1e-12) << "averaging only removes energy (Z_00: none)";
}

// Zonal data whose function k is, in w_r, the cell average of sum_j c(k, j) Z_j.
ZonalData SyntheticData(const Eigen::MatrixXd& c, int order, double theta_step, double phi_step) {
  ZonalData d;
  d.theta_min_rad = kZone.theta_min_rad();
  d.theta_max_rad = kZone.theta_max_rad();
  d.order = order;
  d.grid = MakeExitantGrid(kZone, theta_step, phi_step);
  const ZonalBasis zb(kZone, order);
  const Eigen::MatrixXd a = CellIntegrals(d.grid, zb);
  d.functions.resize(zb.size());
  for (int k = 0; k < zb.size(); ++k) {
    GridImage& f = d.functions[k];
    f.filled.assign(d.grid.cells(), 0);
    for (int ch = 0; ch < 3; ++ch) {
      f.value[ch].resize(d.grid.cells());
      f.variance[ch].assign(d.grid.cells(), 0.01f * (ch + 1));
      f.weight[ch].resize(d.grid.cells());
      for (int cell = 0; cell < d.grid.cells(); ++cell) {
        const double area = d.grid.CellSolidAngle(cell / d.grid.n_phi);
        f.value[ch][cell] = static_cast<float>((ch + 1) * a.row(cell).dot(c.row(k)) / area);
        f.weight[ch][cell] = static_cast<float>(area);
      }
    }
  }
  return d;
}

TEST(ProjectExitant, RecoversTensorCoefficientsOfABandLimitedBrdf) {
  const int order = 3, n = ShCount(order);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd c(n, n);
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < n; ++j) c(k, j) = normal(rng);
  }
  ZonalData d = SyntheticData(c, order, 1.0, 2.0);
  ProjectExitant(&d);
  for (int ch = 0; ch < 3; ++ch) {
    // Exact for band-limited data, up to the float storage of the grid values (6e-8 relative,
    // summed over ~8500 cells with random signs).
    EXPECT_LT((d.tensor[ch] - (ch + 1) * c).cwiseAbs().maxCoeff(), 2e-6 * (ch + 1) * c.cwiseAbs().maxCoeff());
  }
  // Independent cells of variance s2: var(z_kj) = s2 sum_c A_cj^2 ~ s2 * |cell| * (Gram_jj = 1).
  const double cell_area = d.grid.CellSolidAngle(d.grid.n_theta / 2);
  EXPECT_NEAR(d.tensor_variance[0](2, 5), 0.01 * cell_area, 0.2 * 0.01 * cell_area);
}

TEST(ZonalExr, RoundTripKeepsEverything) {
  const int order = 2, n = ShCount(order);
  Eigen::MatrixXd c = Eigen::MatrixXd::Identity(n, n) * 0.3;
  c(1, 4) = -0.05;
  ZonalData d = SyntheticData(c, order, 5.0, 10.0);
  d.functions[0].filled[7] = 1;
  d.attributes = {{"rig", "thesis"}, {"material", "lambertian:0.18"}};
  ProjectExitant(&d);
  const std::string path = TempPath("rt.exr");
  WriteZonalExr(path, d);
  const ZonalData back = ReadZonalExr(path);
  EXPECT_DOUBLE_EQ(back.theta_min_rad, d.theta_min_rad);
  EXPECT_DOUBLE_EQ(back.theta_max_rad, d.theta_max_rad);
  EXPECT_EQ(back.order, order);
  EXPECT_EQ(back.grid.n_theta, d.grid.n_theta);
  EXPECT_EQ(back.grid.n_phi, d.grid.n_phi);
  EXPECT_EQ(back.attributes, d.attributes);
  ASSERT_EQ(back.functions.size(), d.functions.size());
  for (int k = 0; k < n; ++k) {
    for (int ch = 0; ch < 3; ++ch) {
      EXPECT_EQ(back.functions[k].value[ch], d.functions[k].value[ch]) << "float storage is exact";
      EXPECT_EQ(back.functions[k].variance[ch], d.functions[k].variance[ch]);
    }
  }
  EXPECT_EQ(back.functions[0].weight[1], d.functions[0].weight[1]);
  EXPECT_EQ(back.functions[3].filled[7], 1);
  EXPECT_EQ(back.functions[3].filled[8], 0);
  for (int ch = 0; ch < 3; ++ch) {
    // The tensor is stored as float: relative rounding 6e-8.
    EXPECT_LT((back.tensor[ch] - d.tensor[ch]).cwiseAbs().maxCoeff(), 1e-7 * (ch + 1));
  }
  fs::remove(path);
}

TEST(ZonalExr, DamagedMissingOrForeignFilesAreNamedInputErrors) {
  const std::string missing = TempPath("missing.exr");
  EXPECT_THROW(ReadZonalExr(missing), InputError);

  const int n = ShCount(2);
  ZonalData d = SyntheticData(Eigen::MatrixXd::Identity(n, n), 2, 5.0, 10.0);
  ProjectExitant(&d);
  const std::string path = TempPath("cut.exr");
  WriteZonalExr(path, d);
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes.substr(0, bytes.size() / 2);
  try {
    ReadZonalExr(path);
    FAIL() << "a truncated zonal.exr was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  std::ofstream(path, std::ios::binary | std::ios::trunc) << "not an EXR file at all";
  EXPECT_THROW(ReadZonalExr(path), InputError);
  fs::remove(path);
}

// Found by the stress suite (tools/stress.h, zonal group): WriteZonalExr stored NaN, and doubles
// beyond float range as Inf, without a word; the reader then checked only the grid values, so a
// non-finite tensor coefficient or variance reached the SH conversion and the fits. Now neither
// side lets one through (the reader's side is exercised by the stress cases zonal-read-*, which
// damage a file on disk).
TEST(ZonalExr, NonFiniteOrOverflowingValuesAreNeverWritten) {
  const int n = ShCount(2);
  const ZonalData good = SyntheticData(Eigen::MatrixXd::Identity(n, n), 2, 5.0, 10.0);
  ZonalData projected = good;
  ProjectExitant(&projected);
  const std::string path = TempPath("nan.exr");
  struct Damage {
    const char* name;
    std::function<void(ZonalData*)> apply;
    const char* named;  // what the message must name
  };
  const std::vector<Damage> damages = {
      {"NaN tensor", [](ZonalData* d) { d->tensor[1](3, 2) = std::nan(""); }, "z.G(3, 2)"},
      {"tensor beyond float", [](ZonalData* d) { d->tensor[0](0, 1) = 1e39; }, "z.R(0, 1)"},
      {"Inf variance", [](ZonalData* d) { d->tensor_variance[2](1, 1) = INFINITY; }, "var.B(1, 1)"},
      {"negative variance", [](ZonalData* d) { d->functions[2].variance[0][4] = -1; }, "Z1_0.var.R"},
      {"NaN grid value", [](ZonalData* d) { d->functions[1].value[1][0] = NAN; }, "Z1_-1.G"},
  };
  for (const Damage& damage : damages) {
    ZonalData d = projected;
    damage.apply(&d);
    fs::remove(path);
    try {
      WriteZonalExr(path, d);
      ADD_FAILURE() << damage.name << " was written";
    } catch (const NumericalError& e) {
      EXPECT_NE(std::string(e.what()).find(damage.named), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(path)) << damage.name;
  }
  WriteZonalExr(path, projected);  // undamaged data still write and read
  EXPECT_NO_THROW(ReadZonalExr(path));
  fs::remove(path);
}

// Found by fuzz/zonal_exr_fuzz: OpenEXR 3.1 allocates header attributes at the size the file
// declares, and reads a channel list by its own layout whatever its declared size, so a 3.5 KB
// file whose channel list was cut short made it read the next bytes as a 1.9 GB string. The
// header is checked before OpenEXR sees it (brdf/exr_header.h).
TEST(ZonalExr, HeaderAttributesLargerThanTheFileAreInputErrors) {
  const std::string fuzzed = ZBRDF_TEST_DATA_DIR "/fuzz/zonal-channel-list-cut-short.exr";
  try {
    ReadZonalExr(fuzzed);
    FAIL() << "a corrupt header was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("OpenEXR header attribute 'channels'"), std::string::npos)
        << e.what();
  }
  // A valid file whose zbrdf.attributes string claims 1.9 GB.
  const int n = ShCount(1);
  ZonalData d = SyntheticData(Eigen::MatrixXd::Identity(n, n), 1, 5.0, 10.0);
  ProjectExitant(&d);
  const std::string path = TempPath("huge-attribute.exr");
  WriteZonalExr(path, d);
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  const std::string key("zbrdf.attributes\0string\0", 24);
  const size_t at = bytes.find(key);
  ASSERT_NE(at, std::string::npos);
  bytes.replace(at + key.size(), 4, std::string("\0\0\0\x74", 4));
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  try {
    ReadZonalExr(path);
    FAIL() << "an attribute larger than the file was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'zbrdf.attributes' declares 1946157056 bytes"),
              std::string::npos)
        << e.what();
  }
  fs::remove(path);
}

TEST(PixelToGrid, ConstantFieldStaysConstantAndTheCameraTilesTheZone) {
  const testing::FastThesisRig& rig = testing::SharedFastThesisRig();
  const RigCalibration cal = NominalCalibration(rig.rig, rig.maps);
  const ExitantGrid g = MakeExitantGrid(kZone, 1.0, 2.0);
  const PixelToGrid resampler(cal, g);
  const size_t pixels = cal.camera_response.size();
  std::vector<float> value(pixels, 2.5f), variance(pixels, 0.04f);
  std::vector<uint8_t> valid(pixels, 1);
  const GridImage image = resampler.Resample(value, variance, valid);
  // Bayer RGGB: a quarter of the pixels are red, half green, a quarter blue; their footprints
  // together cover the zone once.
  const double fraction[3] = {0.25, 0.5, 0.25};
  for (int ch = 0; ch < 3; ++ch) {
    double total_weight = 0;
    for (int cell = 0; cell < g.cells(); ++cell) {
      ASSERT_NEAR(image.value[ch][cell], 2.5f, 1e-5f) << ch << " " << cell;
      total_weight += image.weight[ch][cell];
      if (image.weight[ch][cell] > 0) {
        // Averaging N equal-weight pixels divides the variance by about N >= 1.
        EXPECT_LE(image.variance[ch][cell], 0.04f * 1.0001f);
        EXPECT_GT(image.variance[ch][cell], 0.0f);
      }
    }
    EXPECT_NEAR(total_weight / kZone.solid_angle_sr(), fraction[ch], 0.03 * fraction[ch]) << ch;
  }
}

TEST(PixelToGrid, SmoothFieldGivesCellAverages) {
  // value = cos(theta_r) of each pixel's direction: the cell values must match the cell
  // averages of cos(theta) to within the footprint's resolution (~1/4 of a fast-preset pixel).
  const testing::FastThesisRig& rig = testing::SharedFastThesisRig();
  const RigCalibration cal = NominalCalibration(rig.rig, rig.maps);
  const ExitantGrid g = MakeExitantGrid(kZone, 1.0, 2.0);
  const PixelToGrid resampler(cal, g);
  const size_t pixels = cal.camera_response.size();
  std::vector<float> value(pixels, 0.0f), variance(pixels, 0.0f);
  std::vector<uint8_t> valid(pixels, 1);
  for (size_t p = 0; p < pixels; ++p) {
    if (cal.CameraValid(static_cast<int>(p))) value[p] = static_cast<float>(cal.CameraDirection(static_cast<int>(p)).z);
  }
  const GridImage image = resampler.Resample(value, variance, valid);
  double worst = 0;
  for (int i = 0; i < g.n_theta; ++i) {
    const double c0 = std::cos(g.ThetaHigh(i)), c1 = std::cos(g.ThetaLow(i));
    const double average = 0.5 * (c0 + c1);  // cos(theta) is uniform in solid angle
    for (int j = 0; j < g.n_phi; ++j) {
      if (image.weight[1][i * g.n_phi + j] <= 0) continue;
      worst = std::max(worst, std::abs(image.value[1][i * g.n_phi + j] - average));
    }
  }
  // A fast-preset pixel spans ~1 deg; the cos(theta) slope is at most sin(56.5 deg) per radian.
  EXPECT_LT(worst, 0.83 * DegToRad(1.0)) << worst;
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
