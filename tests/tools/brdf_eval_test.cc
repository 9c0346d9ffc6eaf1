// zbrdf eval: parsing, evaluation and output, against the published reference values of the
// measured networks and against closed forms of the analytic models written here from their
// papers (not from the model code).
#include "tools/brdf_eval.h"

#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "basis/error.h"
#include "tools/brdf_input.h"
#include "tools_test_util.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

using testing::Rng;
using testing::TempDir;

// Parses CSV output back into its seven columns per line (after the header).
std::vector<std::array<double, 7>> ParseCsv(const std::string& text) {
  std::vector<std::array<double, 7>> rows;
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "theta_i,phi_i,theta_o,phi_o,r,g,b");
  while (std::getline(in, line)) {
    std::array<double, 7> row{};
    const char* p = line.data();
    const char* end = p + line.size();
    for (int c = 0; c < 7; ++c) {
      const auto result = std::from_chars(p, end, row[c]);
      EXPECT_EQ(result.ec, std::errc()) << line;
      p = result.ptr + 1;
    }
    rows.push_back(row);
  }
  return rows;
}

// Evaluates text through the whole pipeline: parse, evaluate, format, parse the output back.
std::vector<std::array<double, 7>> RunPipeline(const std::string& spec, const std::string& text) {
  const BrdfInput input = ResolveBrdfInput(spec);
  const std::vector<DirectionPair> pairs = ParseDirectionPairs(text, "test");
  const std::vector<Rgb> f = EvaluatePairs(*input.brdf, pairs);
  return ParseCsv(FormatEvaluations(pairs, f, EvalFormat::kCsv, spec, input.brdf->Spec()));
}

TEST(Eval, NetworkMaterialsMatchTheReferenceTable) {
  // The table in data/materials/README.md: | material | theta_i | phi_i | theta_o | phi_o | R G B |
  std::ifstream readme(std::string(ZBRDF_SOURCE_DIR) + "/data/materials/README.md");
  ASSERT_TRUE(readme);
  std::string line;
  int rows = 0;
  while (std::getline(readme, line)) {
    if (line.rfind("| ", 0) != 0 || line.find("---") != std::string::npos ||
        line.find("material") != std::string::npos) {
      continue;
    }
    std::vector<std::string> cells;
    std::stringstream ss(line.substr(1));
    std::string cell;
    while (std::getline(ss, cell, '|')) cells.push_back(cell);
    ASSERT_GE(cells.size(), 6u) << line;
    const std::string material = cells[0].substr(1, cells[0].find_last_not_of(' '));
    const std::string pair_text =
        cells[1] + " " + cells[2] + " " + cells[3] + " " + cells[4] + "\n";
    std::istringstream rgb_text(cells[5]);
    double ref[3];
    rgb_text >> ref[0] >> ref[1] >> ref[2];
    const auto out = RunPipeline("merl:" + material, pair_text);
    ASSERT_EQ(out.size(), 1u);
    for (int c = 0; c < 3; ++c) {
      // 1e-4 relative, except where the table's own rounding is coarser: it prints values
      // rounded to 6 decimal places (then to 6 significant digits), so a value of 0.001 is only
      // known to +-5e-7, i.e. 5e-4 relative (the chrome row).
      const double tolerance = std::max(1e-4 * ref[c], 5e-7);
      EXPECT_NEAR(out[0][4 + c], ref[c], tolerance) << material << " " << pair_text;
    }
    ++rows;
  }
  EXPECT_EQ(rows, 16);
}

// ---- closed forms (from the papers; see fitting/ for the models' references) ----

double Schlick(double f0, double cos_theta) {
  return f0 + (1 - f0) * std::pow(1 - std::clamp(cos_theta, 0.0, 1.0), 5);
}

struct Angles {
  Vec3 wi, wo, h;
  double theta_h, phi_h;
};
Angles AnglesOf(const std::array<double, 7>& row) {
  Angles a;
  a.wi = {std::sin(row[0]) * std::cos(row[1]), std::sin(row[0]) * std::sin(row[1]),
          std::cos(row[0])};
  a.wo = {std::sin(row[2]) * std::cos(row[3]), std::sin(row[2]) * std::sin(row[3]),
          std::cos(row[2])};
  a.h = Normalize(a.wi + a.wo);
  a.theta_h = std::acos(a.h.z);
  a.phi_h = std::atan2(a.h.y, a.h.x);
  return a;
}

using ClosedForm = std::function<Rgb(const Angles&)>;

struct ModelCase {
  std::string spec;
  ClosedForm f;
  bool reciprocal;
};

std::vector<ModelCase> Cases() {
  std::vector<ModelCase> cases;
  cases.push_back(
      {"lambert:0.2,0.5,0.8", [](const Angles&) { return Rgb(0.2, 0.5, 0.8) / M_PI; }, true});
  cases.push_back({"blinn-phong:kd=0.1,0.2,0.3,ks=0.5,n=40",
                   [](const Angles& a) {
                     const double lobe = 48.0 / (8 * M_PI) * std::pow(std::cos(a.theta_h), 40);
                     return Rgb(0.1, 0.2, 0.3) / M_PI + Rgb(0.5 * lobe);
                   },
                   true});
  // Ward 1992 / Ghosh eq. 2.8: delta the half vector's polar angle, phi its azimuth.
  cases.push_back({"ward:rho_d=0.1,rho_s=0.05,0.1,0.2,alpha_x=0.15,alpha_y=0.35",
                   [](const Angles& a) {
                     const double t2 = std::pow(std::tan(a.theta_h), 2);
                     const double e = std::exp(-t2 * (std::pow(std::cos(a.phi_h) / 0.15, 2) +
                                                      std::pow(std::sin(a.phi_h) / 0.35, 2)));
                     const double lobe = e / (4 * M_PI * 0.15 * 0.35 * std::sqrt(a.wi.z * a.wo.z));
                     return Rgb(0.1 / M_PI) + Rgb(0.05, 0.1, 0.2) * lobe;
                   },
                   true});
  // Ashikhmin & Shirley 2000, eqs. 4-5.
  cases.push_back({"as:rd=0.4,0.3,0.2,rs=0.05,nu=200,nv=20",
                   [](const Angles& a) {
                     const double e =
                         200 * std::pow(std::cos(a.phi_h), 2) + 20 * std::pow(std::sin(a.phi_h), 2);
                     const double kh = Dot(a.wi, a.h);
                     const double spec = std::sqrt(201.0 * 21.0) / (8 * M_PI) *
                                         std::pow(std::cos(a.theta_h), e) /
                                         (kh * std::max(a.wi.z, a.wo.z)) * Schlick(0.05, kh);
                     const double angular = 28.0 / (23 * M_PI) * 0.95 *
                                            (1 - std::pow(1 - a.wi.z / 2, 5)) *
                                            (1 - std::pow(1 - a.wo.z / 2, 5));
                     return Rgb(spec) + Rgb(0.4, 0.3, 0.2) * angular;
                   },
                   true});
  // GGX (Walter et al. 2007), anisotropic form with the Smith height-correlated G2 (Heitz 2014).
  cases.push_back({"ggx:alpha_x=0.2,alpha_y=0.4,F0=0.9,0.6,0.3,kd=0.05",
                   [](const Angles& a) {
                     const double ax = 0.2, ay = 0.4;
                     const double c = std::cos(a.phi_h), s = std::sin(a.phi_h),
                                  t2 = std::pow(std::tan(a.theta_h), 2);
                     const double d =
                         1 / (M_PI * ax * ay * std::pow(std::cos(a.theta_h), 4) *
                              std::pow(1 + t2 * (c * c / (ax * ax) + s * s / (ay * ay)), 2));
                     auto lambda = [&](const Vec3& w) {
                       const double phi = std::atan2(w.y, w.x), theta = std::acos(w.z);
                       const double alpha2 =
                           std::pow(std::cos(phi) * ax, 2) + std::pow(std::sin(phi) * ay, 2);
                       return (-1 + std::sqrt(1 + alpha2 * std::pow(std::tan(theta), 2))) / 2;
                     };
                     const double g2 = 1 / (1 + lambda(a.wi) + lambda(a.wo));
                     const double common = d * g2 / (4 * a.wi.z * a.wo.z);
                     const double oh = Dot(a.wo, a.h);
                     return Rgb(0.05 / M_PI) +
                            Rgb(Schlick(0.9, oh), Schlick(0.6, oh), Schlick(0.3, oh)) * common;
                   },
                   true});
  // D-BRDF (Ashikhmin & Premoze 2007, Ghosh eq. 2.13) with a constant p(h): normalized so that
  // integral p cos dw = 1, p = 1 / pi.
  cases.push_back({"dbrdf:c=0.5,0.4,0.3,F0=0.2,kd=0.1,theta_samples=2,p=1,1",
                   [](const Angles& a) {
                     const double spec = (1 / M_PI) * Schlick(0.2, Dot(a.wi, a.h)) /
                                         (a.wi.z + a.wo.z - a.wi.z * a.wo.z);
                     return Rgb(0.5, 0.4, 0.3) * spec + Rgb(0.1 / M_PI);
                   },
                   true});
  return cases;
}

std::string RandomPairsText(int n, uint64_t seed, double theta_max) {
  Rng rng(seed);
  std::string text = "# random pairs\n";
  char line[160];
  for (int k = 0; k < n; ++k) {
    std::snprintf(line, sizeof(line), "%.17g %.17g, %.17g\t%.17g\n", theta_max * rng.Uniform(),
                  2 * M_PI * rng.Uniform(), theta_max * rng.Uniform(), 2 * M_PI * rng.Uniform());
    text += line;
    if (k % 97 == 0) text += "\n   # a comment line\n";
  }
  return text;
}

TEST(Eval, AnalyticModelsMatchTheirClosedForms) {
  const std::string text = RandomPairsText(2000, 5, 0.5 * M_PI * 0.999);
  for (const ModelCase& model : Cases()) {
    const auto rows = RunPipeline(model.spec, text);
    ASSERT_EQ(rows.size(), 2000u);
    for (const auto& row : rows) {
      const Angles a = AnglesOf(row);
      const Rgb expected = model.f(a);
      for (int c = 0; c < 3; ++c) {
        // Different but equivalent formulas in double precision: rounding of order 1e-15 times
        // the formulas' condition numbers (tan near grazing, powers up to 200): 1e-9 relative.
        ASSERT_NEAR(row[4 + c], expected[c], 1e-9 * std::abs(expected[c]) + 1e-300)
            << model.spec << " at " << row[0] << " " << row[1] << " " << row[2] << " " << row[3];
      }
    }
  }
}

TEST(Eval, ReciprocalModelsAreReciprocal) {
  const std::string text = RandomPairsText(500, 9, 0.5 * M_PI * 0.999);
  const std::vector<DirectionPair> pairs = ParseDirectionPairs(text, "test");
  std::vector<DirectionPair> swapped;
  for (const DirectionPair& p : pairs) swapped.push_back({p.theta_o, p.phi_o, p.theta_i, p.phi_i});
  for (const ModelCase& model : Cases()) {
    ASSERT_TRUE(model.reciprocal);
    const BrdfInput input = ResolveBrdfInput(model.spec);
    ASSERT_TRUE(input.brdf->IsReciprocal()) << model.spec;
    const auto f = EvaluatePairs(*input.brdf, pairs), g = EvaluatePairs(*input.brdf, swapped);
    for (size_t k = 0; k < f.size(); ++k) {
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(f[k][c], g[k][c], 1e-12 * f[k][c]) << model.spec;
    }
  }
}

TEST(Eval, BelowTheHorizonIsZero) {
  const auto rows =
      RunPipeline("lambert:0.5", "2.0 0 0.3 0\n0.3 0 1.6 1\n1.5707963267948966 0 0.2 0\n");
  ASSERT_EQ(rows.size(), 3u);
  for (int c = 4; c < 7; ++c) {
    EXPECT_EQ(rows[0][c], 0.0);
    EXPECT_EQ(rows[1][c], 0.0);
  }
  // cos(pi/2) rounds to 6e-17 > 0: just above the horizon, f_r of a Lambertian surface.
  EXPECT_NEAR(rows[2][4], 0.5 / M_PI, 1e-15);
}

TEST(Eval, OutputRoundTripsEveryDouble) {
  const std::string text = RandomPairsText(300, 13, 1.5);
  const std::vector<DirectionPair> pairs = ParseDirectionPairs(text, "test");
  const auto rows = RunPipeline("ggx:alpha=0.3", text);
  ASSERT_EQ(rows.size(), pairs.size());
  const BrdfInput input = ResolveBrdfInput("ggx:alpha=0.3");
  for (size_t k = 0; k < rows.size(); ++k) {
    EXPECT_EQ(rows[k][0], pairs[k].theta_i);
    EXPECT_EQ(rows[k][1], pairs[k].phi_i);
    EXPECT_EQ(rows[k][2], pairs[k].theta_o);
    EXPECT_EQ(rows[k][3], pairs[k].phi_o);
    const Rgb f = input.brdf->Eval(SphericalDirection(pairs[k].theta_i, pairs[k].phi_i),
                                   SphericalDirection(pairs[k].theta_o, pairs[k].phi_o));
    EXPECT_EQ(rows[k][4], f.r);  // %.17g is exact
  }
}

TEST(Eval, MalformedLinesNameTheirLineNumber) {
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"0.1 0.2 0.3 0.4\n# fine\n0.1 0.2 0.3\n", "line 3"},
      {"0.1 0.2 0.3 0.4\n\n\n0.1 0.2 x 0.4\n", "line 4"},
      {"0.1,,0.2 0.3 0.4\n", "line 1"},
      {"0.1 0.2 0.3 0.4 0.5\n", "line 1"},
      {"0.1 0.2 0.3 nan\n", "line 1"},
      {"0.1 0.2 0.3 inf\n", "line 1"},
      {"0.1 0.2 0.3 0.4,\n", "line 1"},
  };
  for (const auto& [text, where] : bad) {
    try {
      ParseDirectionPairs(text, "pairs.txt");
      FAIL() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("pairs.txt " + where), std::string::npos) << e.what();
    }
  }
  // Many lines, parsed in parallel chunks: the first bad line is the one reported.
  std::string big;
  for (int k = 0; k < 50000; ++k) big += (k == 30001 || k == 45000) ? "1 2 3\n" : "1 2 3 4\n";
  try {
    ParseDirectionPairs(big, "big");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("big line 30002:"), std::string::npos) << e.what();
  }
}

TEST(Eval, JsonOutput) {
  const std::vector<DirectionPair> pairs = {{0.1, 0.2, 0.3, 0.4}};
  const std::vector<Rgb> f = {Rgb(0.25, std::nan(""), 1.0 / 3.0)};
  const std::string json = FormatEvaluations(pairs, f, EvalFormat::kJson, "in", "spec");
  EXPECT_NE(json.find("\"units\": \"1/sr\""), std::string::npos);
  EXPECT_NE(json.find("[0.10000000000000001,0.20000000000000001,0.29999999999999999,"
                      "0.40000000000000002,0.25,null,0.33333333333333331]"),
            std::string::npos)
      << json;
}

TEST(EvalCommand, FailedRunWritesNothingAndSuccessWritesTheFile) {
  TempDir dir("eval_cli");
  testing::WriteFile(dir.File("good.txt"), "0.3 0 0.3 3.14159265\n");
  testing::WriteFile(dir.File("bad.txt"), "0.3 0 0.3 3.14159265\n0.3 0 zero 1\n");
  EXPECT_EQ(testing::RunZbrdf(
                "eval lambert:0.5 --pairs " + dir.File("bad.txt") + " --out " + dir.File("bad.csv"),
                "/dev/null", dir.File("err.txt")),
            2);
  EXPECT_FALSE(std::filesystem::exists(dir.File("bad.csv")));
  EXPECT_NE(testing::ReadFile(dir.File("err.txt")).find("line 2"), std::string::npos);
  EXPECT_EQ(testing::RunZbrdf("eval merl:red-fabric --pairs " + dir.File("good.txt") + " --out " +
                              dir.File("good.json")),
            0);
  const std::string json = testing::ReadFile(dir.File("good.json"));
  EXPECT_NE(json.find("\"rows\""), std::string::npos);
  // Standard input to standard output, CSV.
  EXPECT_EQ(testing::RunZbrdf("eval lambert:0.5 < " + dir.File("good.txt"), dir.File("out.csv")),
            0);
  const auto rows = ParseCsv(testing::ReadFile(dir.File("out.csv")));
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_NEAR(rows[0][4], 0.5 / M_PI, 1e-16);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
