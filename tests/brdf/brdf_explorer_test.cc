// BRDF Explorer export: the file's structure, and the round trip through the parameters and
// tables it holds back to the same BRDF (numbers are written in float precision, which is what
// BRDF Explorer's GPU evaluates).
#include "brdf/brdf_explorer.h"

#include <gtest/gtest.h>

#include <regex>
#include <string>

#include "basis/error.h"
#include "brdf/dbrdf.h"
#include "brdf/ggx.h"
#include "brdf/material_spec.h"
#include "brdf_checks.h"
#include "tests/test_files.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

using testing::Rng;
using testing::TempDir;

void ExpectRoundTrip(const Brdf& original, const std::string& name, double tolerance) {
  TempDir dir("explorer_" + name);
  const std::string path = dir.File(name + ".brdf");
  WriteBrdfExplorerFile(path, original);
  const std::string text = testing::ReadFile(path);
  // The file type line, the parameter and shader blocks and the entry point BRDF Explorer calls.
  EXPECT_EQ(text.rfind("analytic\n", 0), 0u);
  const size_t params_begin = text.find("::begin parameters"),
               params_end = text.find("::end parameters");
  const size_t shader_begin = text.find("::begin shader"), shader_end = text.find("::end shader");
  ASSERT_NE(params_begin, std::string::npos);
  ASSERT_LT(params_begin, params_end);
  ASSERT_LT(params_end, shader_begin);
  ASSERT_LT(shader_begin, shader_end);
  EXPECT_NE(text.find("vec3 BRDF( vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y )"), std::string::npos);
  // Braces balance in the shader.
  int depth = 0;
  for (size_t i = shader_begin; i < shader_end; ++i) {
    depth += text[i] == '{' ? 1 : text[i] == '}' ? -1 : 0;
    ASSERT_GE(depth, 0);
  }
  EXPECT_EQ(depth, 0);
  // Parameter lines are "float NAME MIN MAX DEFAULT" with MIN <= DEFAULT <= MAX, or colors.
  const std::regex float_line(R"(float (\w+) (\S+) (\S+) (\S+))");
  const std::string params = text.substr(params_begin, params_end - params_begin);
  for (auto it = std::sregex_iterator(params.begin(), params.end(), float_line);
       it != std::sregex_iterator(); ++it) {
    const double lo = std::stod((*it)[2]), hi = std::stod((*it)[3]), v = std::stod((*it)[4]);
    EXPECT_LE(lo, v) << (*it)[0];
    EXPECT_LE(v, hi) << (*it)[0];
  }
  // Float literals in arrays carry a '.' or an exponent (GLSL reads "1" as an int).
  const std::regex int_literal(R"([(,]\s*-?\d+\s*[,)])");
  const size_t arrays = text.find("float[");
  if (arrays != std::string::npos) {
    const std::string tables = text.substr(arrays, shader_end - arrays);
    const std::string before_functions = tables.substr(
        0, tables.find("\nfloat P(") == std::string::npos ? tables.find("\nvec3 BRDF")
                                                          : tables.find("\nfloat P("));
    EXPECT_FALSE(std::regex_search(before_functions, int_literal));
  }
  const auto back = ReadBrdfExplorerFile(path);
  Rng rng(21);
  for (int k = 0; k < 400; ++k) {
    const Vec3 w_i = testing::RandomUpperDirection(rng, 0.02),
               w_o = testing::RandomUpperDirection(rng, 0.02);
    const Rgb a = original.Eval(w_i, w_o), b = back->Eval(w_i, w_o);
    for (int c = 0; c < 3; ++c) {
      ASSERT_NEAR(b[c], a[c], tolerance * std::abs(a[c]) + 1e-12) << name << " channel " << c;
    }
  }
}

// Float precision (9 significant digits) of each parameter, amplified by the models' exponents:
// a relative change e in an exponent n changes f by n e |log(cos)|; 1e-6 covers them all.
TEST(BrdfExplorer, AnalyticModelsRoundTrip) {
  ExpectRoundTrip(*MakeBrdf("lambert:0.2,0.5,0.8"), "lambert", 1e-7);
  ExpectRoundTrip(*MakeBrdf("blinn-phong:kd=0.1,ks=0.4,0.5,0.6,n=120"), "blinn", 1e-6);
  ExpectRoundTrip(*MakeBrdf("ward:rho_d=0.1,rho_s=0.05,alpha_x=0.12,alpha_y=0.3"), "ward", 1e-6);
  ExpectRoundTrip(*MakeBrdf("as:rd=0.3,rs=0.05,0.06,0.07,nu=300,nv=30"), "as", 1e-6);
  ExpectRoundTrip(*MakeBrdf("ggx:alpha_x=0.1234567,alpha_y=0.3,F0=0.9,0.6,0.3,kd=0.05"), "ggx",
                  1e-6);
}

TEST(BrdfExplorer, DBrdfTableRoundTrips) {
  // An anisotropic table: 10 theta x 6 phi values.
  DBrdfParams params;
  params.p_h.theta_samples = 10;
  params.p_h.phi_samples = 6;
  for (int j = 0; j < 10; ++j) {
    for (int k = 0; k < 6; ++k)
      params.p_h.p.push_back(std::exp(-0.5 * j) * (1.0 + 0.3 * std::cos(k)));
  }
  params.p_h.Normalize();
  params.c = Rgb(0.3, 0.2, 0.1);
  params.f0 = 0.35;
  params.kd = Rgb(0.02, 0.03, 0.04);
  ExpectRoundTrip(DBrdf(params), "dbrdf", 1e-6);
}

TEST(BrdfExplorer, NetworkRoundTrips) {
  // The MLP's weights as arrays; float rounding of 675 weights through exp(): 1e-5.
  ExpectRoundTrip(*MakeBrdf("merl:gold-metallic-paint"), "network", 1e-5);
}

TEST(BrdfExplorer, TablesAndMirrorsAreRefusedWithAPointer) {
  try {
    BrdfExplorerSource(*MakeBrdf("mirror:0.9"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--format merl"), std::string::npos) << e.what();
  }
}

TEST(BrdfExplorer, ForeignFilesAreNotReadAsData) {
  TempDir dir("explorer_foreign");
  testing::WriteFile(
      dir.File("disney.brdf"),
      "analytic\n::begin parameters\nfloat roughness 0 1 .5\n::end parameters\n"
      "::begin shader\nvec3 BRDF( vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y ) { return vec3(0); }\n"
      "::end shader\n");
  EXPECT_THROW(ReadBrdfExplorerFile(dir.File("disney.brdf")), InputError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
