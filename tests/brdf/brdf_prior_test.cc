#include "brdf/brdf_prior.h"

#include <Imath/half.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "basis/error.h"
#include "brdf/blinn_phong.h"
#include "brdf/dbrdf_file.h"
#include "brdf/ggx.h"
#include "brdf/lambertian.h"
#include "brdf/tabulated_file.h"
#include "tests/test_files.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

using testing::TempDir;

std::vector<PriorSource> Sources() {
  return {{"white", std::make_shared<LambertianBrdf>(Rgb(0.9, 0.8, 0.7)), "lambert:0.9"},
          {"glossy", std::make_shared<GgxBrdf>(0.3, 0.3, Rgb(0.9, 0.5, 0.1), Rgb(0.05)), "ggx"},
          {"plastic", std::make_shared<BlinnPhongBrdf>(Rgb(0.3), Rgb(0.2), 40.0), "phong"}};
}

// A BRDF that is NaN (or infinite) at some pairs.
class Broken final : public Brdf {
 public:
  explicit Broken(double bad) : bad_(bad) {}
  Rgb Eval(const Vec3& w_i, const Vec3&) const override {
    return w_i.z > 0.9 ? Rgb(0.1, bad_, 0.1) : Rgb(0.1);
  }
  bool IsReciprocal() const override { return false; }
  bool IsEnergyConserving() const override { return false; }
  std::string Spec() const override { return "broken"; }

 private:
  double bad_;
};

// An OpenEXR file with string attributes and a HALF channel "f" (or none), for files the
// writer never produces.
void WriteExr(const std::string& path, int width, int height,
              const std::vector<std::pair<std::string, std::string>>& attributes,
              std::vector<float> f, bool with_f = true) {
  Imf::Header header(width, height);
  for (const auto& [name, value] : attributes) header.insert(name, Imf::StringAttribute(value));
  f.resize(static_cast<size_t>(width) * height, 0.5f);
  std::vector<half> data(f.begin(), f.end());
  std::vector<float> other(f.size(), 0.5f);
  Imf::FrameBuffer fb;
  if (with_f) {
    header.channels().insert("f", Imf::Channel(Imf::HALF));
    fb.insert("f", Imf::Slice(Imf::HALF, reinterpret_cast<char*>(data.data()), sizeof(half),
                              sizeof(half) * width));
  } else {
    header.channels().insert("R", Imf::Channel(Imf::FLOAT));
    fb.insert("R", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(other.data()), sizeof(float),
                              sizeof(float) * width));
  }
  Imf::OutputFile file(path.c_str(), header);
  file.setFrameBuffer(fb);
  file.writePixels(height);
}

// Reading `path` throws InputError whose message names the file (and contains `also`).
void ExpectRejected(const std::string& path, const std::string& also = "") {
  try {
    (void)ReadPriorFile(path);
    ADD_FAILURE() << "read " << path;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(also), std::string::npos) << e.what();
  }
}

// BuildPrior's error for `sources` names `name`.
void ExpectBuildRejects(const std::vector<PriorSource>& sources, const std::string& name) {
  try {
    (void)BuildPrior(sources, HalfDiffGrid(4, 4, 3));
    ADD_FAILURE() << "built a prior with " << name;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
  }
}

TEST(BrdfPriorTest, AtomsAreTheTablesOfTheSources) {
  const HalfDiffGrid grid(8, 6, 4);
  const std::vector<PriorSource> sources = Sources();
  const BrdfPrior prior = BuildPrior(sources, grid);
  EXPECT_EQ(prior.grid, grid);
  ASSERT_EQ(prior.material_count(), 3);
  ASSERT_EQ(prior.atoms.rows(), grid.size());
  ASSERT_EQ(prior.atoms.cols(), 9);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(prior.materials[k], sources[k].name);
    EXPECT_EQ(prior.sources[k], sources[k].source);
    EXPECT_EQ(prior.MaterialIndex(sources[k].name), k);
    const std::vector<Rgb> table = TabulateBrdf(*sources[k].brdf, grid);
    for (int n = 0; n < grid.size(); ++n) {
      for (int c = 0; c < 3; ++c) {
        ASSERT_EQ(prior.atoms(n, 3 * k + c), static_cast<float>(table[n][c])) << k << " " << n;
      }
    }
  }
  EXPECT_EQ(prior.MaterialIndex("absent"), -1);
  EXPECT_EQ(prior.info["materials"], 3);
}

TEST(BrdfPriorTest, BadSourcesAreRejectedNamingTheMaterial) {
  EXPECT_THROW(BuildPrior({}, HalfDiffGrid(4, 4, 3)), InputError);
  std::vector<PriorSource> twice = Sources();
  twice.push_back({"glossy", std::make_shared<LambertianBrdf>(Rgb(0.5)), "again"});
  ExpectBuildRejects(twice, "glossy");
  ExpectBuildRejects({Sources()[0], {"black-hole", std::make_shared<LambertianBrdf>(Rgb(0)), "x"}},
                     "black-hole");
  ExpectBuildRejects({{"not-a-number", std::make_shared<Broken>(std::nan("")), "x"}},
                     "not-a-number");
  ExpectBuildRejects(
      {{"infinite", std::make_shared<Broken>(std::numeric_limits<double>::infinity()), "x"}},
      "infinite");
}

TEST(BrdfPriorTest, RoundTripKeepsHalfPrecisionAndScalesLargeAtoms) {
  const TempDir dir("brdf_prior_round_trip");
  const HalfDiffGrid grid(6, 5, 3);
  BrdfPrior prior = BuildPrior(Sources(), grid);
  // Values over half's whole normal range in one atom, and an atom above half's range (a sharp
  // peak of 3e6 / sr), which the writer scales.
  for (int n = 0; n < grid.size(); ++n) {
    prior.atoms(n, 4) = static_cast<float>(std::pow(10.0, -4.0 + 8.7 * n / (grid.size() - 1.0)));
    prior.atoms(n, 7) = static_cast<float>(3e6 * std::pow(1e-4, n / (grid.size() - 1.0)));
  }
  prior.atoms(3, 2) = 1e-6f;  // below half's normal range (6.1e-5): a subnormal half
  prior.info["note"] = "round trip";
  const std::string path = dir.File("prior.exr");
  WritePriorFile(path, prior);
  const BrdfPrior read = ReadPriorFile(path);
  EXPECT_EQ(read.grid, grid);
  EXPECT_EQ(read.materials, prior.materials);
  EXPECT_EQ(read.sources, prior.sources);
  EXPECT_EQ(read.info, prior.info);
  ASSERT_EQ(read.atoms.rows(), prior.atoms.rows());
  ASSERT_EQ(read.atoms.cols(), prior.atoms.cols());
  for (int a = 0; a < prior.atoms.cols(); ++a) {
    const double scale = std::max(1.0, prior.atoms.col(a).maxCoeff() / 60000.0);
    for (int n = 0; n < grid.size(); ++n) {
      const double v = prior.atoms(n, a), r = read.atoms(n, a);
      if (v / scale >= 6.1035e-5) {
        // Half's 11-bit significand rounds to 2^-11 = 4.9e-4 relative: the stated 5e-4 (the
        // scale and float rounding add 1e-7).
        EXPECT_NEAR(r, v, 5e-4 * v) << a << " " << n;
      } else {
        // Subnormal halves are spaced 2^-24 (times the scale): rounding errs by half of that.
        EXPECT_NEAR(r, v, 0x1p-25 * scale) << a << " " << n;
      }
    }
  }
  EXPECT_EQ(prior.atoms(3, 2), 1e-6f);
  EXPECT_NEAR(read.atoms(3, 2), 1e-6, 0x1p-25);
  EXPECT_GT(read.atoms.col(7).maxCoeff(), 2.99e6);  // scaled, not clipped to 65504
}

TEST(BrdfPriorTest, HashChangesWithAnyValueNameOrGrid) {
  const BrdfPrior prior = BuildPrior(Sources(), HalfDiffGrid(5, 4, 3));
  BrdfPrior same = prior;
  EXPECT_EQ(same.Hash(), prior.Hash());
  BrdfPrior value = prior;
  value.atoms(17, 5) = std::nextafter(value.atoms(17, 5), 1.0f);
  EXPECT_NE(value.Hash(), prior.Hash());
  BrdfPrior name = prior;
  name.materials[1] = "glossy2";
  EXPECT_NE(name.Hash(), prior.Hash());
  // The same atom values on another grid shape (5 x 4 x 3 and 4 x 5 x 3 have equal sizes).
  BrdfPrior grid = prior;
  grid.grid = HalfDiffGrid(4, 5, 3);
  EXPECT_NE(grid.Hash(), prior.Hash());
}

TEST(BrdfPriorTest, WriterRejectsAtomsThatDoNotMatch) {
  const TempDir dir("brdf_prior_write");
  BrdfPrior prior = BuildPrior(Sources(), HalfDiffGrid(4, 4, 3));
  prior.atoms.conservativeResize(prior.atoms.rows(), 8);
  const std::string path = dir.File("prior.exr");
  try {
    WritePriorFile(path, prior);
    ADD_FAILURE() << "wrote a prior with 8 atoms for 3 materials";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  EXPECT_THROW(WritePriorFile(dir.File("no-such-folder/prior.exr"),
                              BuildPrior(Sources(), HalfDiffGrid(4, 4, 3))),
               InputError);
}

TEST(BrdfPriorTest, FilesThatAreNotPriorsAreInputErrorsNamingThem) {
  const TempDir dir("brdf_prior_not_ours");
  const std::string good = dir.File("good.exr");
  WritePriorFile(good, BuildPrior(Sources(), HalfDiffGrid(4, 4, 3)));
  const std::string bytes = testing::ReadFile(good);
  ExpectRejected(dir.File("missing.exr"));
  testing::WriteFile(dir.File("garbage.exr"), std::string("\x76\x2f\x31\x01garbage", 11));
  ExpectRejected(dir.File("garbage.exr"));
  testing::WriteFile(dir.File("text.exr"), "not an image");
  ExpectRejected(dir.File("text.exr"));
  for (const size_t keep : {size_t{40}, bytes.size() / 2, bytes.size() - 8}) {
    const std::string cut = dir.File("truncated-" + std::to_string(keep) + ".exr");
    testing::WriteFile(cut, bytes.substr(0, keep));
    ExpectRejected(cut);
  }
  const std::string tabulated = dir.File("fit-prior.exr");
  WriteTabulatedFile(
      tabulated, TabulatedBrdf(HalfDiffGrid(2, 2, 2), std::vector<Rgb>(8, Rgb(0.1)), {}, "t"), {});
  ExpectRejected(tabulated, "not a zbrdf prior");
  DBrdfParams params;
  params.p_h.theta_samples = 4;
  params.p_h.phi_samples = 1;
  params.p_h.p = {4, 3, 2, 1};
  params.p_h.Normalize();
  const std::string dbrdf = dir.File("fit-dbrdf.exr");
  WriteDBrdfFile(dbrdf, DBrdf(params), {});
  ExpectRejected(dbrdf, "not a zbrdf prior");
  const std::string zonal = dir.File("zonal.exr");
  WriteExr(zonal, 3, 3, {{"zbrdf.format", "zbrdf-zonal-v1"}}, {});
  ExpectRejected(zonal, "not a zbrdf prior");
}

TEST(BrdfPriorTest, DamagedPriorsAreInputErrorsNamingTheFileAndTheProblem) {
  const TempDir dir("brdf_prior_damaged");
  const std::pair<std::string, std::string> format{"zbrdf.format", "zbrdf-prior-v1"};
  const std::pair<std::string, std::string> grid{"zbrdf.grid", "2 2 2"};  // 8 nodes
  const auto atoms = [](const std::string& a, const std::string& b, const std::string& c) {
    return std::pair<std::string, std::string>{"zbrdf.atoms", "[" + a + "," + b + "," + c + "]"};
  };
  const std::string atom = R"({"material": "m", "channel": "R", "scale": 1, "source": "s"})";
  const auto good_atoms = atoms(atom, atom, atom);
  int count = 0;
  const auto expect = [&](int width, int height,
                          const std::vector<std::pair<std::string, std::string>>& attributes,
                          std::vector<float> f, const std::string& problem, bool with_f = true) {
    const std::string path = dir.File("damaged-" + std::to_string(++count) + ".exr");
    WriteExr(path, width, height, attributes, std::move(f), with_f);
    ExpectRejected(path, problem);
  };
  expect(8, 3, {format, good_atoms}, {}, "zbrdf.grid is missing");
  expect(8, 3, {format, {"zbrdf.grid", "2 x 2"}, good_atoms}, {}, "three node counts");
  expect(8, 3, {format, {"zbrdf.grid", "2 2 1"}, good_atoms}, {}, "[2, 512]");
  expect(8, 3, {format, grid}, {}, "zbrdf.atoms is missing");
  expect(8, 3, {format, grid, {"zbrdf.atoms", "{}"}}, {}, "3 atoms per material");
  expect(8, 2, {format, grid, {"zbrdf.atoms", "[" + atom + "," + atom + "]"}}, {},
         "3 atoms per material");
  expect(8, 3, {format, grid, {"zbrdf.atoms", "[1, 2"}}, {}, "3 atoms per material");
  expect(9, 3, {format, grid, good_atoms}, {}, "the image is 9 x 3");
  expect(8, 3, {format, grid, good_atoms}, {}, "channel f is missing", false);
  expect(8, 3, {format, grid, atoms(atom, atom, R"({"material": "m", "scale": "1"})")}, {},
         "numeric scale");
  expect(8, 3, {format, grid, atoms(atom, R"({"material": "m", "scale": -2})", atom)}, {},
         "must be finite and > 0");
  expect(8, 3, {format, grid, atoms(atom, R"({"material": "m", "scale": 0})", atom)}, {},
         "must be finite and > 0");
  expect(8, 3, {format, grid, atoms(atom, R"({"material": "other", "scale": 1})", atom)}, {},
         "one material's R, G, B");
  expect(8, 3, {format, grid, good_atoms}, {0.5f, -0.5f}, "values must be finite and >= 0");
  expect(8, 3, {format, grid, good_atoms}, {std::nanf("")}, "values must be finite and >= 0");
  expect(8, 3, {format, grid, good_atoms}, {std::numeric_limits<float>::infinity()},
         "values must be finite and >= 0");
  // A large scale times a large half overflows float.
  expect(8, 3, {format, grid, atoms(R"({"material": "m", "scale": 1e300})", atom, atom)}, {},
         "values must be finite and >= 0");
  expect(8, 3, {format, grid, good_atoms, {"zbrdf.info", "[unclosed"}}, {}, "zbrdf.info");
  // The same header with nothing wrong reads.
  const std::string fine = dir.File("fine.exr");
  WriteExr(fine, 8, 3, {format, grid, good_atoms}, {});
  const BrdfPrior prior = ReadPriorFile(fine);
  EXPECT_EQ(prior.materials, std::vector<std::string>{"m"});
  EXPECT_EQ(prior.sources, std::vector<std::string>{"s"});
  EXPECT_EQ(prior.atoms(7, 2), 0.5f);
}

TEST(BrdfPriorTest, TheBundledPriorReads) {
  const BrdfPrior prior = ReadPriorFile(DefaultPriorPath());
  EXPECT_EQ(prior.material_count(), 100);
  EXPECT_EQ(prior.grid, HalfDiffGrid());
  EXPECT_GE(prior.MaterialIndex("chrome"), 0);
  EXPECT_GT(prior.atoms.minCoeff(), -1e-30f);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
