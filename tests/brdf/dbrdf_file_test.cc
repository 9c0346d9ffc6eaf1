#include "brdf/dbrdf_file.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "basis/error.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

std::string TempPath(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / "zbrdf-dbrdf-file-test";
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

DBrdf MakeModel(int theta_samples, int phi_samples) {
  DBrdfParams params;
  params.p_h.theta_samples = theta_samples;
  params.p_h.phi_samples = phi_samples;
  for (int j = 0; j < theta_samples; ++j) {
    for (int k = 0; k < phi_samples; ++k) {
      params.p_h.p.push_back(std::exp(-0.1 * j) * (1.0 + 0.3 * std::cos(2.0 * k * 2 * M_PI / phi_samples)) + 1e-3);
    }
  }
  params.p_h.Normalize();
  params.c = Rgb(0.3, 0.5, 0.7);
  params.f0 = 0.17;
  params.kd = Rgb(0.05, 0.1, 0.2);
  return DBrdf(params);
}

TEST(DBrdfFileTest, RoundTripsToFloatPrecision) {
  for (const auto& [theta, phi] : {std::pair{91, 1}, std::pair{46, 8}}) {
    const DBrdf model = MakeModel(theta, phi);
    const std::string path = TempPath("model.exr");
    const nlohmann::json info = {{"model", "dbrdf"}, {"note", "test"}};
    WriteDBrdfFile(path, model, info);
    const std::unique_ptr<DBrdf> read = ReadDBrdfFile(path);
    EXPECT_EQ(read->table().theta_samples, theta);
    EXPECT_EQ(read->table().phi_samples, phi);
    EXPECT_DOUBLE_EQ(read->f0(), model.f0());
    EXPECT_EQ(read->kd(), model.kd());
    // p is stored in float (relative 6e-8) and renormalized, the factor folded into c: f_r agrees
    // to a few float ulps.
    for (const Vec3& w_i : {Vec3{0.3, 0.1, 0.95}, Vec3{-0.5, 0.2, 0.84}}) {
      for (const Vec3& w_o : {Vec3{0.0, 0.0, 1.0}, Vec3{0.6, -0.3, 0.74}}) {
        const Rgb a = model.Eval(Normalize(w_i), Normalize(w_o)), b = read->Eval(Normalize(w_i), Normalize(w_o));
        for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(b[ch], a[ch], 3e-7 * a[ch]);
      }
    }
    EXPECT_EQ(ReadDBrdfFileInfo(path), info);
  }
}

TEST(DBrdfFileTest, RejectsFilesThatAreNotDBrdfFiles) {
  const std::string text = TempPath("not-an-exr.exr");
  std::ofstream(text) << "hello";
  EXPECT_THROW(ReadDBrdfFile(text), InputError);
  EXPECT_THROW(ReadDBrdfFile(TempPath("missing.exr")), InputError);
  try {
    ReadDBrdfFile(TempPath("missing.exr"));
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.exr"), std::string::npos);
  }
  EXPECT_THROW(WriteDBrdfFile("/nonexistent-folder/x.exr", MakeModel(3, 1), {}), InputError);
}

// Found by fuzz/dbrdf_file_fuzz: a data window off the origin made the frame buffer's base pointer
// point before the table (undefined behaviour). Such files are rejected by name.
TEST(DBrdfFileTest, ADataWindowOffTheOriginIsAnInputError) {
  const std::string fuzzed = ZBRDF_TEST_DATA_DIR "/fuzz/dbrdf-window-off-origin.exr";
  try {
    ReadDBrdfFile(fuzzed);
    FAIL() << "read a file whose data window is off the origin";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(fuzzed), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("does not start at (0, 0)"), std::string::npos) << e.what();
  }
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
