#include "brdf/merl_table.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "basis/error.h"
#include "brdf_checks.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

constexpr int kTh = 90, kTd = 90, kPd = 180;
constexpr size_t kBins = static_cast<size_t>(kTh) * kTd * kPd;
constexpr double kScale[3] = {1.0 / 1500, 1.15 / 1500, 1.66 / 1500};

// The value this test stores for channel c of bin (i, j, k), in file units. Every 997th bin of
// the red channel is marked unmeasured (-1), as MERL's files do.
double StoredValue(int c, int i, int j, int k) {
  const size_t index = (static_cast<size_t>(i) * kTd + j) * kPd + k;
  if (c == 0 && index % 997 == 3) return -1.0;
  return 1.0 + i + 0.01 * j + 0.0001 * k + 0.5 * c;
}

// An independent MERL writer: int32 dimensions, then planar float64 channels, in the host's
// (little-endian) byte order, as MERL's own tools write them.
std::vector<char> MerlFileBytes() {
  static_assert(std::endian::native == std::endian::little);
  std::vector<char> bytes(12 + 3 * kBins * 8);
  const int32_t dims[3] = {kTh, kTd, kPd};
  std::memcpy(bytes.data(), dims, 12);
  char* values = bytes.data() + 12;
  for (int c = 0; c < 3; ++c) {
    for (int i = 0; i < kTh; ++i) {
      for (int j = 0; j < kTd; ++j) {
        for (int k = 0; k < kPd; ++k) {
          const double v = StoredValue(c, i, j, k);
          std::memcpy(values + (c * kBins + (static_cast<size_t>(i) * kTd + j) * kPd + k) * 8, &v,
                      8);
        }
      }
    }
  }
  return bytes;
}

// A per-process path in the temp folder, so that tests running in parallel do not collide.
std::string TempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / (std::to_string(getpid()) + "_" + name))
      .string();
}

std::string WriteBytes(const std::string& name, const std::vector<char>& bytes, size_t size) {
  const std::string path = TempPath(name);
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  file.write(bytes.data(), static_cast<std::streamsize>(size));
  return path;
}

// Directions at the centre of bin (i, j, k), built independently of the reader: rotate the
// difference vector (theta_d, phi_d) and its reciprocal (-d.x, -d.y, d.z) by theta_h about y,
// then phi_h about z.
void BinCentre(int i, int j, int k, double phi_h, Vec3* w_i, Vec3* w_o) {
  const double theta_h = std::pow((i + 0.5) / kTh, 2) * M_PI / 2;
  const double theta_d = (j + 0.5) / kTd * M_PI / 2;
  const double phi_d = (k + 0.5) / kPd * M_PI;
  const auto rotate = [&](const Vec3& v) {
    const Vec3 a{v.x * std::cos(theta_h) + v.z * std::sin(theta_h), v.y,
                 -v.x * std::sin(theta_h) + v.z * std::cos(theta_h)};
    return Vec3{a.x * std::cos(phi_h) - a.y * std::sin(phi_h),
                a.x * std::sin(phi_h) + a.y * std::cos(phi_h), a.z};
  };
  const Vec3 d = SphericalDirection(theta_d, phi_d);
  *w_i = rotate(d);
  *w_o = rotate(Vec3{-d.x, -d.y, d.z});
}

class MerlTableTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    bytes_ = new std::vector<char>(MerlFileBytes());
    path_ = new std::string(WriteBytes("zbrdf_merl_test.binary", *bytes_, bytes_->size()));
    brdf_ = MerlBrdf::FromFile(*path_).release();
  }
  static void TearDownTestSuite() {
    std::filesystem::remove(*path_);
    delete brdf_;
    delete path_;
    delete bytes_;
  }

  static std::vector<char>* bytes_;
  static std::string* path_;
  static MerlBrdf* brdf_;
};

std::vector<char>* MerlTableTest::bytes_ = nullptr;
std::string* MerlTableTest::path_ = nullptr;
MerlBrdf* MerlTableTest::brdf_ = nullptr;

TEST_F(MerlTableTest, EvaluatesStoredValuesAtBinCentres) {
  testing::Rng rng(91);
  int checked = 0;
  for (int n = 0; n < 20000; ++n) {
    const int i = static_cast<int>(rng.Uniform() * kTh), j = static_cast<int>(rng.Uniform() * kTd);
    const int k = static_cast<int>(rng.Uniform() * kPd);
    Vec3 w_i, w_o;
    BinCentre(i, j, k, 2 * M_PI * rng.Uniform(), &w_i, &w_o);
    if (w_i.z <= 1e-9 || w_o.z <= 1e-9) continue;  // outside the hemisphere: f = 0
    ++checked;
    const Rgb f = brdf_->Eval(w_i, w_o);
    const Rgb swapped = brdf_->Eval(w_o, w_i);  // phi_d + pi folds to the same bin
    for (int c = 0; c < 3; ++c) {
      const double expected = std::max(0.0, StoredValue(c, i, j, k) * kScale[c]);
      ASSERT_NEAR(f[c], expected, 1e-15 * expected) << i << " " << j << " " << k << " c" << c;
      ASSERT_EQ(swapped[c], f[c]);
    }
  }
  EXPECT_GT(checked, 5000);
  EXPECT_EQ(brdf_->Spec(), "file:" + *path_);
  EXPECT_TRUE(brdf_->IsReciprocal());
  // Random pairs too: exchanging w_i and w_o lands in the same bin (up to a pair falling within
  // rounding of a bin edge, about 1e-13 per pair).
  EXPECT_EQ(testing::MaxReciprocityError(*brdf_, 93), 0.0);
}

TEST_F(MerlTableTest, CountsUnmeasuredEntriesAndEvaluatesThemAsZero) {
  // Bins with index % 997 == 3 in the red channel are negative.
  int64_t expected = 0;
  for (size_t index = 0; index < kBins; ++index) expected += index % 997 == 3;
  EXPECT_EQ(brdf_->invalid_entry_count(), expected);
  // Bin (0, 0, 3) (index 3) is one of them.
  Vec3 w_i, w_o;
  BinCentre(0, 0, 3, 0.3, &w_i, &w_o);
  const Rgb f = brdf_->Eval(w_i, w_o);
  EXPECT_EQ(f.r, 0.0);
  EXPECT_NEAR(f.g, StoredValue(1, 0, 0, 3) * kScale[1], 1e-15);
}

TEST_F(MerlTableTest, SamplesWithItsProxy) {
  // Checks that Sample and Pdf are the proxy's, consistently. The proxy's density is piecewise
  // constant in theta_h with the half-vector Jacobian: its normalization integrated over half
  // vectors on the proxy's cells, to ~1e-9 (see proxy_sampler_test.cc), and a cubature of 1e-4
  // per bin.
  EXPECT_SAMPLING_MATCHES_PDF(*brdf_, SphericalDirection(0.6, 1.0), 92, 1e-6,
                              testing::ProxyCellsCubature());
}

TEST_F(MerlTableTest, ZeroBelowTheHorizon) {
  EXPECT_EQ(brdf_->Eval(Vec3{0, 0.6, -0.8}, Vec3{0, 0, 1}), Rgb());
  EXPECT_EQ(brdf_->Eval(Vec3{0, 0, 1}, Vec3{0.6, 0, -0.8}), Rgb());
}

TEST_F(MerlTableTest, WriterRoundTripsAndWritesTheMerlHeader) {
  const std::string path = TempPath("zbrdf_merl_written.binary");
  WriteMerlBinary(path, brdf_->table());
  std::ifstream file(path, std::ios::binary);
  int32_t dims[3] = {0, 0, 0};
  file.read(reinterpret_cast<char*>(dims), 12);
  EXPECT_EQ(dims[0], 90);
  EXPECT_EQ(dims[1], 90);
  EXPECT_EQ(dims[2], 180);
  EXPECT_EQ(std::filesystem::file_size(path), bytes_->size());
  const MerlTable back = ReadMerlBinary(path);
  ASSERT_EQ(back.f.size(), kBins);
  for (size_t index = 0; index < kBins; index += 101) {
    for (int c = 0; c < 3; ++c) {
      // value / scale * scale: two roundings.
      EXPECT_NEAR(back.f[index][c], brdf_->table().f[index][c],
                  4e-16 * std::abs(brdf_->table().f[index][c]));
    }
  }
  std::filesystem::remove(path);
  MerlTable wrong;
  wrong.f.resize(10);
  EXPECT_THROW(WriteMerlBinary(path, wrong), InputError);
}

// Runs ReadMerlBinary on bytes and returns the error message ("" if it did not throw).
std::string ReadError(const std::string& name, const std::vector<char>& bytes, size_t size) {
  const std::string path = WriteBytes(name, bytes, size);
  std::string message;
  try {
    ReadMerlBinary(path);
  } catch (const InputError& e) {
    message = e.what();
  }
  std::filesystem::remove(path);
  return message;
}

TEST_F(MerlTableTest, TruncatedAndCorruptFilesNameTheFileAndTheProblem) {
  const auto expect_error = [](const std::string& message, const std::string& file,
                               const std::string& what) {
    EXPECT_NE(message.find(file), std::string::npos) << message;
    EXPECT_NE(message.find(what), std::string::npos) << message;
  };
  expect_error(ReadError("zbrdf_merl_short.binary", *bytes_, 8), "zbrdf_merl_short.binary",
               "truncated");
  expect_error(ReadError("zbrdf_merl_cut.binary", *bytes_, bytes_->size() - 8),
               "zbrdf_merl_cut.binary", "truncated");
  std::vector<char> copy = *bytes_;
  copy.push_back(0);
  expect_error(ReadError("zbrdf_merl_long.binary", copy, copy.size()), "zbrdf_merl_long.binary",
               "unexpected bytes");
  copy.pop_back();
  const int32_t bad_dims[3] = {90, 90, 360};
  std::memcpy(copy.data(), bad_dims, 12);
  expect_error(ReadError("zbrdf_merl_dims.binary", copy, copy.size()), "zbrdf_merl_dims.binary",
               "dimensions are 90 90 360");
  std::memcpy(copy.data(), bytes_->data(), 12);
  const double nan = std::nan("");
  std::memcpy(copy.data() + 12 + (kBins + 5) * 8, &nan, 8);
  expect_error(ReadError("zbrdf_merl_nan.binary", copy, copy.size()), "zbrdf_merl_nan.binary",
               "green value of bin 5 is not a finite number");
  try {
    ReadMerlBinary("/nonexistent/zbrdf/gold.binary");
    ADD_FAILURE() << "a missing file was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/zbrdf/gold.binary"), std::string::npos);
  }
}

TEST(MerlBinTest, FollowsTheReferenceIndexing) {
  // theta_h = 0: bin 0 whatever the rest; theta_h just below (i/90)^2 pi/2 is in bin i - 1.
  const Vec3 n{0, 0, 1};
  EXPECT_EQ(MerlBinOf(n, n).theta_half, 0);
  EXPECT_EQ(MerlBinOf(n, n).theta_diff, 0);
  const double edge = std::pow(40.0 / 90.0, 2) * M_PI / 2;
  for (const auto& [theta_h, bin] : {std::pair{edge * (1 - 1e-9), 39}, {edge * (1 + 1e-9), 40}}) {
    const Vec3 h = SphericalDirection(theta_h, 0.0);
    EXPECT_EQ(MerlBinOf(h, h).theta_half, bin);
  }
  // Grazing difference angles clamp to the last bins.
  const Vec3 a = SphericalDirection(M_PI / 2 - 1e-12, 0.0), b = SphericalDirection(M_PI / 2, M_PI);
  EXPECT_EQ(MerlBinOf(a, b).theta_diff, 89);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
