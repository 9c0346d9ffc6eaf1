#include "brdf/material_spec.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "basis/data_path.h"
#include "basis/error.h"
#include "brdf/dbrdf.h"
#include "brdf/ggx.h"
#include "brdf/lambertian.h"
#include "brdf_checks.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

// Evaluations of two BRDFs agree exactly at random pairs.
void ExpectSameBrdf(const Brdf& a, const Brdf& b) {
  testing::Rng rng(121);
  for (int n = 0; n < 50; ++n) {
    const Vec3 w_i = testing::RandomUpperDirection(rng), w_o = testing::RandomUpperDirection(rng);
    EXPECT_EQ(a.Eval(w_i, w_o), b.Eval(w_i, w_o)) << a.Spec();
    EXPECT_EQ(a.Pdf(w_o, w_i), b.Pdf(w_o, w_i)) << a.Spec();
  }
}

TEST(MaterialSpecTest, CanonicalSpecsRoundTrip) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"lambert:0.18", "lambert:albedo=0.18"},
      {"lambert:0.5,0.4,0.3", "lambert:albedo=0.5,0.4,0.3"},
      {"Lambertian: albedo = 0.18", "lambert:albedo=0.18"},
      {"blinn-phong:kd=0.1,ks=0.5,n=100", "blinn-phong:kd=0.1,ks=0.5,n=100"},
      {"blinn-phong:ks=0.5,n=10", "blinn-phong:kd=0,ks=0.5,n=10"},
      {"ward:rho_d=0.1,rho_s=0.05,alpha_x=0.1,alpha_y=0.3",
       "ward:rho_d=0.1,rho_s=0.05,alpha_x=0.1,alpha_y=0.3"},
      {"ward:rho_s=0.05,alpha=0.2", "ward:rho_d=0,rho_s=0.05,alpha_x=0.2,alpha_y=0.2"},
      {"as:rd=0.3,rs=0.05,nu=100,nv=10", "as:rd=0.3,rs=0.05,nu=100,nv=10"},
      {"ggx:alpha=0.2,F0=0.04,kd=0.1,0.2,0.5", "ggx:alpha=0.2,F0=0.04,kd=0.1,0.2,0.5"},
      {"ggx:alpha=0.2", "ggx:alpha=0.2,F0=0.04,kd=0"},
      {"GGX:alpha_x=0.1,alpha_y=0.3,f0=0.9,0.6,0.2",
       "ggx:alpha_x=0.1,alpha_y=0.3,F0=0.9,0.6,0.2,kd=0"},
      {"mirror:R=0.95", "mirror:R=0.95"},
      {"mirror:0.9", "mirror:R=0.9"},
      {"merl:blue-acrylic", "merl:blue-acrylic"},
  };
  for (const auto& [spec, canonical] : cases) {
    const auto brdf = MakeBrdf(spec);
    EXPECT_EQ(brdf->Spec(), canonical) << spec;
    const auto again = MakeBrdf(brdf->Spec());
    EXPECT_EQ(again->Spec(), canonical) << spec;
    ExpectSameBrdf(*brdf, *again);
  }
  // Numbers print in their shortest exact form, so arbitrary doubles survive.
  const GgxBrdf odd(0.1 + 0.2, 1.0 / 3.0, Rgb(0.04, 1e-300, 0.999999999999), Rgb(M_PI / 10));
  const auto back = MakeBrdf(odd.Spec());
  EXPECT_EQ(back->Spec(), odd.Spec());
  ExpectSameBrdf(odd, *back);
}

TEST(MaterialSpecTest, DBrdfSpecsRoundTripAndNormalizeTheirTable) {
  // p = 1 integrates to pi: the table is rescaled, and the canonical spec is normalized.
  const auto brdf = MakeBrdf("dbrdf:theta_samples=3,p=1,1,1");
  const auto* dbrdf = dynamic_cast<const DBrdf*>(brdf.get());
  ASSERT_NE(dbrdf, nullptr);
  EXPECT_NEAR(dbrdf->table().p[0], 1 / M_PI, 1e-15);
  EXPECT_EQ(dbrdf->f0(), 0.04);
  EXPECT_EQ(dbrdf->c(), Rgb(1));
  const auto again = MakeBrdf(brdf->Spec());
  EXPECT_EQ(again->Spec(), brdf->Spec());
  ExpectSameBrdf(*brdf, *again);
  const auto aniso =
      MakeBrdf("dbrdf:c=0.5,0.6,0.7,F0=0.1,kd=0.2,theta_samples=3,phi_samples=2,p=3,3,2,1,0.5,0");
  EXPECT_EQ(MakeBrdf(aniso->Spec())->Spec(), aniso->Spec());
}

TEST(MaterialSpecTest, FilesByExtension) {
  const std::string json = DataPath("data/materials/merl/chrome.json");
  const auto network = MakeBrdf("file:" + json);
  EXPECT_EQ(network->Spec(), "file:" + json);
  ExpectSameBrdf(*network, *MakeBrdf("merl:chrome"));
}

// The InputError message of MakeBrdf(spec), or "" if it succeeded.
std::string SpecError(const std::string& spec) {
  try {
    MakeBrdf(spec);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(MaterialSpecTest, ErrorsNameTheSpecAndTheBadPart) {
  EXPECT_EQ(SpecError("ggx:alpah=0.2"),
            "material 'ggx:alpah=0.2': unknown parameter 'alpah' for ggx; valid: alpha, alpha_x, "
            "alpha_y, F0, kd");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"gold", "expected MODEL:PARAMETERS"},
      {"foo:1",
       "unknown model 'foo'; valid: lambert, blinn-phong, ward, as, ggx, dbrdf, mirror, retro, "
       "merl, rgl, file"},
      {"lambert:", "empty value in the parameters of lambert"},
      {"lambert:0.1,,0.3", "empty value"},
      {"lambert:0.1,0.2", "albedo takes one value (gray) or three (r,g,b), got 2"},
      {"lambert:-0.1", "lambert: albedo must be >= 0 (got -0.1)"},
      {"lambert:nan", "albedo must be a finite number (got nan)"},
      {"lambert:inf", "albedo must be a finite number (got inf)"},
      {"lambert:abc", "'abc' is not a number (in albedo)"},
      {"lambert:0.5x", "'0.5x' is not a number (in albedo)"},
      {"lambert:albedo=", "parameter albedo has no value"},
      {"lambert:albedo=0.1,albedo=0.2", "parameter albedo is given twice"},
      {"blinn-phong:ks=0.5", "missing parameter n for blinn-phong"},
      {"blinn-phong:0.5", "'0.5' has no parameter name; write KEY=VALUE with KEY one of kd, ks, n"},
      {"blinn-phong:ks=0.5,n=1,2", "n takes one value (got 2)"},
      {"ward:rho_s=0.1,alpha=0.1,alpha_x=0.2", "give either alpha or alpha_x and alpha_y"},
      {"ward:rho_s=0.1,alpha_x=0.2", "missing parameter alpha_y for ward"},
      {"ward:rho_s=0.1", "missing parameter alpha (or alpha_x and alpha_y) for ward"},
      {"ggx:alpha=0", "ggx: alpha_x must be > 0 (got 0)"},
      {"ggx:alpha=-0.2", "ggx: alpha_x must be > 0 (got -0.2)"},
      {"ggx:alpha=0.2,F0=1.5", "ggx: F0 must be in [0, 1] (got 1.5)"},
      {"as:rs=0.1,nu=-1,nv=1", "as: nu must be >= 0 (got -1)"},
      {"mirror:R=1.2", "mirror: R must be in [0, 1] (got 1.2)"},
      {"dbrdf:theta_samples=2.5,p=1,1", "theta_samples must be a whole number (got 2.5)"},
      {"dbrdf:theta_samples=3,p=1,1", "p has 2 values, expected theta_samples * phi_samples = 3"},
      {"dbrdf:theta_samples=2,p=0,0", "cannot normalize p(h)"},
      {"dbrdf:theta_samples=2,p=1,-1", "p[1] must be finite and >= 0 (got -1)"},
      {"merl:", "merl: needs a material name"},
      {"merl:chrom", "unknown measured material 'chrom'; did you mean 'chrome'"},
      {"file:", "file: needs a path"},
      {"file:gold.txt", "cannot tell the format of 'gold.txt' from its extension"},
      {"file:/nonexistent/gold.exr", "/nonexistent/gold.exr"},
      {"file:/nonexistent/gold.bsdf", "/nonexistent/gold.bsdf"},
      {"file:/nonexistent/gold.binary", "MERL file /nonexistent/gold.binary: cannot open it"},
      {"file:/nonexistent/gold.json", "network file /nonexistent/gold.json: cannot open it"},
  };
  for (const auto& [spec, part] : cases) {
    const std::string message = SpecError(spec);
    EXPECT_EQ(message.rfind("material '" + spec + "': ", 0), 0u) << spec << " -> " << message;
    EXPECT_NE(message.find(part), std::string::npos) << spec << " -> " << message;
  }
}

TEST(MaterialSpecTest, HelpListsModelsAndBundledMaterials) {
  const std::vector<std::string> models = MaterialModelNames();
  EXPECT_EQ(models.size(), 12u);
  const std::string help = MaterialSpecHelp();
  for (const std::string& model : models) {
    EXPECT_NE(help.find("  " + model + ":"), std::string::npos) << model;
  }
  for (const char* name : {"alum-bronze", "blue-acrylic", "chrome", "yellow-plastic"}) {
    EXPECT_NE(help.find(name), std::string::npos) << name;
  }
  size_t start = 0;
  while (start < help.size()) {
    const size_t end = help.find('\n', start);
    EXPECT_LE(end - start, 100u) << help.substr(start, end - start);
    start = end + 1;
  }
}

TEST(MaterialSpecTest, ShortNamesForTitlesAndFiles) {
  EXPECT_EQ(MaterialShortName("merl:blue-acrylic"), "blue-acrylic");
  EXPECT_EQ(MaterialShortName("MERL:blue-acrylic"), "blue-acrylic");
  EXPECT_EQ(MaterialShortName("file:some/dir/gold.binary"), "gold");
  EXPECT_EQ(MaterialShortName("GGX:alpha=0.2,F0=0.04"), "ggx");
  EXPECT_EQ(MaterialShortName("lambert"), "lambert");
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
