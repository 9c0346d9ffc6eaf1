#include "brdf/tabulated_file.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "basis/data_path.h"
#include "basis/error.h"
#include "brdf/brdf_file.h"
#include "brdf/brdf_prior.h"
#include "brdf/dbrdf_file.h"
#include "brdf/lambertian.h"
#include "brdf/material_spec.h"
#include "brdf/nbrdf.h"
#include "brdf_checks.h"
#include "tests/test_files.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

using testing::Rng;
using testing::TempDir;

// Values over seven decades, so that float rounding is exercised at every scale, and their
// uncertainties.
TabulatedBrdf RandomTable(const HalfDiffGrid& grid, bool with_sigma, uint64_t seed) {
  Rng rng(seed);
  std::vector<Rgb> values(grid.size()), sigma;
  for (Rgb& v : values) {
    for (int c = 0; c < 3; ++c) v[c] = std::pow(10.0, -3.0 + 7.0 * rng.Uniform());
  }
  if (with_sigma) {
    sigma.resize(grid.size());
    for (int n = 0; n < grid.size(); ++n) sigma[n] = 0.1 * rng.Uniform() * values[n];
  }
  return TabulatedBrdf(grid, values, sigma, "random");
}

// An OpenEXR file with the given string attributes and FLOAT channels, for files zbrdf's writer
// never produces.
void WriteExr(const std::string& path, int width, int height,
              const std::vector<std::pair<std::string, std::string>>& attributes,
              std::vector<std::pair<std::string, std::vector<float>>> channels) {
  Imf::Header header(width, height);
  for (const auto& [name, value] : attributes) header.insert(name, Imf::StringAttribute(value));
  Imf::FrameBuffer fb;
  for (auto& [name, values] : channels) {
    values.resize(static_cast<size_t>(width) * height, 0.5f);
    header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    fb.insert(name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(values.data()), sizeof(float),
                               sizeof(float) * width));
  }
  Imf::OutputFile file(path.c_str(), header);
  file.setFrameBuffer(fb);
  file.writePixels(height);
}

// Reading `path` throws InputError whose message names the file (and contains `also`).
void ExpectRejected(const std::string& path, const std::string& also = "") {
  try {
    (void)ReadTabulatedFile(path);
    ADD_FAILURE() << "read " << path;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(also), std::string::npos) << e.what();
  }
}

TEST(TabulatedFileTest, RoundTripsValuesSigmaAndInfoToFloatPrecision) {
  const TempDir dir("tabulated_file_round_trip");
  const HalfDiffGrid grid(6, 5, 3);
  for (const bool with_sigma : {true, false}) {
    const TabulatedBrdf table = RandomTable(grid, with_sigma, 1);
    const std::string path = dir.File(with_sigma ? "sigma.exr" : "plain.exr");
    const nlohmann::json info = {{"model", "prior"}, {"weights", {0.25, 0.75}}};
    WriteTabulatedFile(path, table, info);
    const std::unique_ptr<TabulatedBrdf> read = ReadTabulatedFile(path);
    EXPECT_EQ(read->grid(), grid);
    EXPECT_EQ(read->Spec(), "file:" + path);
    EXPECT_EQ(ReadTabulatedFile(path, "custom")->Spec(), "custom");
    EXPECT_EQ(ReadTabulatedFileInfo(path), info);
    ASSERT_EQ(read->values().size(), table.values().size());
    ASSERT_EQ(read->sigma().size(), table.sigma().size());
    for (int n = 0; n < grid.size(); ++n) {
      for (int c = 0; c < 3; ++c) {
        // Stored as FLOAT: exactly the nearest float, within 2^-24 relative.
        const double v = table.values()[n][c];
        EXPECT_EQ(read->values()[n][c], static_cast<double>(static_cast<float>(v)));
        EXPECT_NEAR(read->values()[n][c], v, 0x1p-24 * v);
        if (with_sigma) {
          EXPECT_EQ(read->sigma()[n][c],
                    static_cast<double>(static_cast<float>(table.sigma()[n][c])));
        }
      }
    }
    // And the model it reads evaluates like the one written: a blend of values each within
    // 2^-24 relative.
    Rng rng(2);
    for (int k = 0; k < 200; ++k) {
      const Vec3 a = testing::RandomUpperDirection(rng), b = testing::RandomUpperDirection(rng);
      const Rgb f = table.Eval(a, b), g = read->Eval(a, b);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(g[c], f[c], 1e-7 * f[c]);
    }
  }
}

TEST(TabulatedFileTest, FilesThatAreNotTabulatedFilesAreInputErrorsNamingThem) {
  const TempDir dir("tabulated_file_not_ours");
  const HalfDiffGrid grid(4, 4, 3);
  const TabulatedBrdf table = RandomTable(grid, false, 3);
  const std::string good = dir.File("good.exr");
  WriteTabulatedFile(good, table, {});
  const std::string bytes = testing::ReadFile(good);

  ExpectRejected(dir.File("missing.exr"));
  testing::WriteFile(dir.File("garbage.exr"), "\x76\x2f\x31\x01 this is not OpenEXR at all");
  ExpectRejected(dir.File("garbage.exr"));
  testing::WriteFile(dir.File("empty.exr"), "");
  ExpectRejected(dir.File("empty.exr"));
  for (const size_t keep : {bytes.size() / 3, bytes.size() - 10}) {
    const std::string cut = dir.File("truncated-" + std::to_string(keep) + ".exr");
    testing::WriteFile(cut, bytes.substr(0, keep));
    ExpectRejected(cut);
  }
  // Other zbrdf files: a D-BRDF fit, a prior, a zonal file's header, an EXR without a format.
  DBrdfParams params;
  params.p_h.theta_samples = 5;
  params.p_h.phi_samples = 1;
  params.p_h.p = {5, 4, 3, 2, 1};
  params.p_h.Normalize();
  const std::string dbrdf = dir.File("fit-dbrdf.exr");
  WriteDBrdfFile(dbrdf, DBrdf(params), {});
  ExpectRejected(dbrdf, "not a zbrdf tabulated BRDF file");
  const std::string prior = dir.File("prior.exr");
  WritePriorFile(prior, BuildPrior({{"white", std::make_shared<LambertianBrdf>(Rgb(0.9)), "x"}},
                                   HalfDiffGrid(2, 2, 2)));
  ExpectRejected(prior, "not a zbrdf tabulated BRDF file");
  const std::string zonal = dir.File("zonal.exr");
  WriteExr(zonal, 3, 2, {{"zbrdf.format", "zbrdf-zonal-v1"}}, {{"R", {}}});
  ExpectRejected(zonal, "not a zbrdf tabulated BRDF file");
  const std::string plain = dir.File("plain.exr");
  WriteExr(plain, 3, 16, {}, {{"R", {}}, {"G", {}}, {"B", {}}});
  ExpectRejected(plain, "not a zbrdf tabulated BRDF file");
  EXPECT_THROW(ReadTabulatedFileInfo(plain), InputError);
}

TEST(TabulatedFileTest, DamagedTablesAreInputErrorsNamingTheFileAndTheProblem) {
  const TempDir dir("tabulated_file_damaged");
  const std::pair<std::string, std::string> format{"zbrdf.format", "zbrdf-tabulated-v1"};
  const std::pair<std::string, std::string> grid{"zbrdf.grid", "2 2 3"};  // 3 x 4 pixels
  const auto rgb = [](std::vector<float> r) {
    return std::vector<std::pair<std::string, std::vector<float>>>{
        {"R", std::move(r)}, {"G", {}}, {"B", {}}};
  };
  int count = 0;
  const auto expect = [&](int width, int height,
                          const std::vector<std::pair<std::string, std::string>>& attributes,
                          std::vector<std::pair<std::string, std::vector<float>>> channels,
                          const std::string& problem) {
    const std::string path = dir.File("damaged-" + std::to_string(++count) + ".exr");
    WriteExr(path, width, height, attributes, std::move(channels));
    ExpectRejected(path, problem);
  };
  expect(3, 4, {format}, rgb({}), "zbrdf.grid is missing");
  expect(3, 4, {format, {"zbrdf.grid", "2 2"}}, rgb({}), "three counts");
  expect(3, 4, {format, {"zbrdf.grid", "1 4 3"}}, rgb({}), "[2, 512]");
  expect(3, 5, {format, grid}, rgb({}), "the image is 3 x 5");
  expect(3, 4, {format, grid}, {{"R", {}}, {"B", {}}}, "channel G is missing");
  expect(3, 4, {format, grid}, rgb({0.5f, -0.25f}), "values must be finite and >= 0");
  expect(3, 4, {format, grid}, rgb({0.5f, std::nanf("")}), "values must be finite and >= 0");
  expect(3, 4, {format, grid}, rgb({std::numeric_limits<float>::infinity()}), "finite");
  auto with_partial_sigma = rgb({});
  with_partial_sigma.push_back({"sigma.R", {}});
  expect(3, 4, {format, grid}, with_partial_sigma, "channel sigma.G is missing");
  expect(3, 4, {format, grid, {"zbrdf.info", "{not json"}}, rgb({}), "zbrdf.info");
  // The same file with a valid table reads.
  const std::string fine = dir.File("fine.exr");
  WriteExr(fine, 3, 4, {format, grid}, rgb({}));
  EXPECT_EQ(ReadTabulatedFile(fine)->values()[0], Rgb(0.5));
}

TEST(TabulatedFileTest, ReadBrdfFileAndMaterialSpecsReadTabulatedFiles) {
  const TempDir dir("tabulated_file_specs");
  const TabulatedBrdf table = RandomTable(HalfDiffGrid(5, 4, 3), true, 4);
  const std::string path = dir.File("fit-prior.exr");
  WriteTabulatedFile(path, table, {{"model", "prior"}});
  const BrdfFile file = ReadBrdfFile(path);
  EXPECT_EQ(file.kind, "tabulated-file");
  const std::unique_ptr<Brdf> spec = MakeBrdf("file:" + path);
  EXPECT_EQ(spec->Spec(), "file:" + path);
  Rng rng(5);
  for (int k = 0; k < 50; ++k) {
    const Vec3 a = testing::RandomUpperDirection(rng), b = testing::RandomUpperDirection(rng);
    const Rgb f = table.Eval(a, b);
    // Both read the float table: the same numbers, within float rounding of the original.
    EXPECT_EQ(file.brdf->Eval(a, b), spec->Eval(a, b));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(spec->Eval(a, b)[c], f[c], 1e-7 * f[c]);
  }
}

TEST(TabulatedFileTest, RglSpecsLoadTheBundledRglNetworks) {
  const std::unique_ptr<Brdf> cardboard = MakeBrdf("rgl:cardboard");
  EXPECT_EQ(cardboard->Spec(), "rgl:cardboard");
  EXPECT_EQ(MaterialShortName("rgl:cardboard"), "cardboard");
  // The same network as the file in data/materials/rgl/, read by path.
  const std::unique_ptr<NbrdfBrdf> file =
      NbrdfBrdf::FromFile(DataPath("data/materials/rgl/cardboard.json"));
  Rng rng(6);
  for (int k = 0; k < 50; ++k) {
    const Vec3 a = testing::RandomUpperDirection(rng), b = testing::RandomUpperDirection(rng);
    const Rgb f = cardboard->Eval(a, b);
    EXPECT_EQ(f, file->Eval(a, b));
    EXPECT_TRUE(f.IsFinite());
    EXPECT_GE(f.Max(), 0.0);
  }
  EXPECT_GT(cardboard->Eval(Vec3{0, 0, 1}, Vec3{0, 0, 1}).Max(), 0.0);
  EXPECT_THROW(MakeBrdf("rgl:no-such-material"), InputError);
  EXPECT_THROW(MakeBrdf("rgl:"), InputError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
