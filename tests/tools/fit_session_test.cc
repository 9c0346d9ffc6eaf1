// End-to-end fits of simulated sessions (tools/fit_session.h): the acceptance tests of
// docs/fitting.md on the thesis rig at the fast preset, order 8.
#include "tools/fit_session.h"

#include <filesystem>
#include <ostream>

#include <gtest/gtest.h>

#include "basis/error.h"
#include "brdf/dbrdf.h"
#include "brdf/dbrdf_file.h"
#include "acquisition/session.h"
#include "acquisition/session_brdf.h"
#include "brdf/brdf_file.h"
#include "brdf/material_spec.h"
#include "brdf/tabulated_brdf.h"
#include "fitting/fit_common.h"
#include "tests/tools/simulated_sessions.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

using testing::SimulatedSession;

Rgb RgbOf(const nlohmann::json& j) { return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()}; }

FitSessionOptions Options(const std::string& model) {
  FitSessionOptions o;
  o.model = model;
  o.write_outputs = false;
  return o;
}

struct GgxCase {
  std::string spec;
  double alpha;
  Rgb f0, kd;
  double kd_tolerance = 0.02;  // relative
};

// What CTest shows next to the test's name (the default prints the object's bytes).
void PrintTo(const GgxCase& c, std::ostream* os) { *os << c.spec; }

class GgxGroundTruthTest : public ::testing::TestWithParam<GgxCase> {};

TEST_P(GgxGroundTruthTest, GgxFitRecoversF0DiffuseAndLobeWidth) {
  const GgxCase& c = GetParam();
  const std::string session = SimulatedSession(c.spec, 8);
  const nlohmann::json r = FitSession(session, Options("ggx")).report;
  ASSERT_TRUE(r["fitted"].get<bool>()) << r.dump(2);
  const nlohmann::json& p = r["params"];
  // Acceptance (docs/fitting.md): F0 and diffuse within 2%, lobe width within 5%. Measured on
  // these sessions: alpha 0.2-0.7%, F0 0.3%, kd 0.5% for alpha 0.3 and 0.5. The capture's
  // coefficients differ from the exact projection of the material by 0.3-0.6% (relative L2 of the
  // isotropic blocks), 15-40x their noise, so the error is systematic; for most materials a
  // 7-parameter fit shrugs it off, but see GgxCase kd_tolerance for alpha 0.1.
  EXPECT_NEAR(p["alpha"].get<double>(), c.alpha, 0.05 * c.alpha);
  const Rgb f0 = RgbOf(p["F0"]), kd = RgbOf(p["kd"]);
  for (int ch = 0; ch < 3; ++ch) {
    EXPECT_NEAR(f0[ch], c.f0[ch], 0.02 * c.f0[ch]) << "F0 channel " << ch;
    EXPECT_NEAR(kd[ch], c.kd[ch], c.kd_tolerance * c.kd[ch]) << "kd channel " << ch;
  }
  EXPECT_LT(r["error_cosine_l2"].get<double>(), 0.05);
  // The D-BRDF cannot represent GGX's 1 / (4 cos cos) geometry (docs/fitting.md), but it fits
  // the zone and stays a valid, finite model.
  const nlohmann::json d = FitSession(session, Options("dbrdf")).report;
  ASSERT_TRUE(d["fitted"].get<bool>());
  EXPECT_LT(d["error_in_zone"].get<double>(), 0.3);
  EXPECT_TRUE(std::isfinite(d["error_cosine_l2"].get<double>()));
}

INSTANTIATE_TEST_SUITE_P(
    Thesis, GgxGroundTruthTest,
    // alpha 0.1, F0 0.9, kd 0.05: the fit of this session's coefficients gives kd 0.0473 (5.5%
    // low; alpha 0.7%, F0 0.3%, error_cosine_l2 0.008). The same fitter on the exact projection of
    // the material (a finer, 1 deg half-vector rule than the fitter's 3 deg one) recovers kd to
    // 1e-4 (analytic_fit_test.cc, RecoversANarrowBrightLobeOverAWeakDiffuse), so the fit is
    // unbiased and the 5.5% is the capture's 0.55% coefficient error (40x its noise) propagated:
    // kd / pi is 1e-4 of the lobe's peak and the lobe's tail is as large as kd / pi from theta_h
    // 30 deg on, so kd carries ~5% of the in-zone signal and a relative coefficient error reaches
    // kd amplified ~10x. The fit's own one-sigma kd (0.00065, scaled by chi2/dof) assumes white
    // errors and understates this by 4x. Tolerance 8%: the measured 5.5% with room for the capture
    // error to grow by 1.4x (0.55% -> 0.8%) before this test flags it.
    ::testing::Values(GgxCase{"ggx:alpha=0.1,F0=0.9,kd=0.05", 0.1, Rgb(0.9), Rgb(0.05), 0.08},
                      GgxCase{"ggx:alpha=0.3,F0=0.04,kd=0.2,0.3,0.4", 0.3, Rgb(0.04), Rgb(0.2, 0.3, 0.4)},
                      GgxCase{"ggx:alpha=0.5,F0=0.5,kd=0.1,0.2,0.3", 0.5, Rgb(0.5), Rgb(0.1, 0.2, 0.3)}),
    // Stable names (CTest registers tests by name; the default prints the object's bytes).
    [](const ::testing::TestParamInfo<GgxCase>& info) {
      return "alpha" + std::to_string(static_cast<int>(std::lround(100 * info.param.alpha)));
    });

TEST(FitSessionTest, LambertianGroundTruthGivesItsAlbedoAndNoSpecularLobe) {
  const Rgb albedo(0.5, 0.4, 0.3);
  const std::string session = SimulatedSession("lambert:0.5,0.4,0.3", 8);
  const nlohmann::json g = FitSession(session, Options("ggx")).report;
  const Rgb kd = RgbOf(g["params"]["kd"]), f0 = RgbOf(g["params"]["F0"]);
  for (int ch = 0; ch < 3; ++ch) {
    EXPECT_NEAR(kd[ch], albedo[ch], 0.02 * albedo[ch]) << ch;
    EXPECT_LT(f0[ch], 0.02);  // the truth is 0: within 2% of F0's range
  }
  const nlohmann::json d = FitSession(session, Options("dbrdf")).report;
  const Rgb dkd = RgbOf(d["params"]["kd"]);
  for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(dkd[ch], albedo[ch], 0.02 * albedo[ch]) << ch;
  EXPECT_LT(d["error_cosine_l2"].get<double>(), 0.05);
}

TEST(FitSessionTest, DBrdfGroundTruthIsRecoveredEndToEnd) {
  // A D-BRDF material (GGX-shaped p, alpha 0.2) through the whole simulated capture.
  DBrdfParams truth;
  std::vector<double> p(91);
  for (int j = 0; j < 91; ++j) p[j] = GgxD(0.2, j * M_PI / 180);
  truth.p_h = HalfVectorTable::Isotropic(p);
  truth.p_h.Normalize();
  truth.c = Rgb(0.4, 0.5, 0.6);
  truth.f0 = 0.5;
  truth.kd = Rgb(0.1, 0.2, 0.3);
  const DBrdf material(truth);
  const std::string session = SimulatedSession(material.Spec(), 8, {0, 3, "-dbrdf-alpha0.2"});
  FitSessionOptions o = Options("dbrdf");
  o.write_outputs = true;
  const FitSessionOutcome outcome = FitSession(session, o);
  const nlohmann::json& r = outcome.report;
  const Rgb kd = RgbOf(r["params"]["kd"]), c = RgbOf(r["params"]["c"]);
  const double f0 = r["params"]["F0"].get<double>();
  for (int ch = 0; ch < 3; ++ch) {
    EXPECT_NEAR(kd[ch], truth.kd[ch], 0.02 * truth.kd[ch]) << ch;
    // The normal-incidence amplitude c F0 is what the zone measures (F0 alone only through the
    // weak Fresnel rise): within 2%.
    EXPECT_NEAR(c[ch] * f0, truth.c[ch] * truth.f0, 0.02 * truth.c[ch] * truth.f0) << ch;
  }
  // p(h) within 5% (relative L2 over the zone's half-vector range, projected measure).
  const DBrdf& fitted = static_cast<const DBrdf&>(*outcome.model);
  double diff = 0, norm = 0;
  for (int j = 0; j <= 55; ++j) {
    const double w = std::sin(j * M_PI / 180) * std::cos(j * M_PI / 180) + 1e-3;
    diff += w * std::pow(fitted.table().p[j] - truth.p_h.p[j], 2);
    norm += w * truth.p_h.p[j] * truth.p_h.p[j];
  }
  EXPECT_LT(std::sqrt(diff / norm), 0.05);
  EXPECT_LT(r["error_in_zone"].get<double>(), 0.05);
  // The outputs: fit-dbrdf.exr reads back to the fitted model, fit-dbrdf.json is the report.
  const std::unique_ptr<DBrdf> read = ReadDBrdfFile(session + "/fit-dbrdf.exr");
  const Vec3 wi = Normalize(Vec3{0.3, 0.2, 0.9}), wo = Normalize(Vec3{-0.3, -0.1, 0.9});
  EXPECT_NEAR(read->Eval(wi, wo).g, fitted.Eval(wi, wo).g, 1e-6 * fitted.Eval(wi, wo).g);
  EXPECT_TRUE(std::filesystem::exists(session + "/fit-dbrdf.json"));
  EXPECT_EQ(ReadDBrdfFileInfo(session + "/fit-dbrdf.exr")["model"], "dbrdf");
}

TEST(FitSessionTest, AnalyticFitsWriteARecreatableSpec) {
  const std::string session = SimulatedSession("lambert:0.5,0.4,0.3", 8);
  for (const char* model : {"ward", "as"}) {
    FitSessionOptions o = Options(model);
    o.write_outputs = true;
    const nlohmann::json r = FitSession(session, o).report;
    const std::string spec = r["spec"].get<std::string>();
    EXPECT_EQ(spec.rfind(std::string(model) + ":", 0), 0u) << spec;
    EXPECT_NO_THROW(MakeBrdf(spec));
    EXPECT_TRUE(std::filesystem::exists(session + "/fit-" + model + ".json"));
    if (std::string(model) == "ward") {
      // Ward contains the Lambertian (rho_s = 0). Measured: 0.0003.
      EXPECT_LT(r["error_cosine_l2"].get<double>(), 0.05) << model;
      continue;
    }
    // Ashikhmin-Shirley does not: its diffuse term 28 Rd (1 - Rs) / (23 pi) g(cos theta_i)
    // g(cos theta_o), g(c) = 1 - (1 - c / 2)^5 (Ashikhmin & Shirley 2000, eq. 5), vanishes at
    // grazing angles, and its specular lobe never does (Schlick's F = (1 - k.h)^5 at Rs = 0, over
    // max(cos theta_i, cos theta_o)). The diffuse term alone, with the Rd best over the whole
    // hemisphere, leaves error_cosine_l2 0.394 (closed form: the integrals separate); with the Rd
    // best over the zone (11.3-54.9 deg), Rs = 0 and the best n (1, the end of the fit's range) the
    // full model leaves 0.063 in the zone and 0.505 over the hemisphere (fit_error.h's
    // quadrature). The fit does better in the zone (measured 0.051) with a broad lobe (n = 1,
    // Rs 0.16-0.30) that flattens g's trend there, at 0.48 over the hemisphere. Limits: in the
    // zone, below that Rs = 0 model's 0.063 (the fit must find at least as good a member of its
    // family); over the hemisphere, 0.505 + 10% for the lobe's extrapolation.
    EXPECT_LT(r["error_in_zone"].get<double>(), 0.063) << model;
    EXPECT_LT(r["error_cosine_l2"].get<double>(), 0.55) << model;
  }
}

TEST(FitSessionTest, Figure33ShRingsAndTheDBrdfDoesNot) {
  // Ghosh 2007, figure 3.3: merl:blue-acrylic at order 10, converted to SH and fitted.
  const std::string session = SimulatedSession("merl:blue-acrylic", 10);
  FitSessionOptions o = Options("dbrdf");
  o.figure_path = testing::TestBuildDir("test-figures") + "/figure-3-3.png";
  std::filesystem::remove(o.figure_path);
  const nlohmann::json r = FitSession(session, o).report;
  ASSERT_TRUE(r.contains("figure"));
  const nlohmann::json& f = r["figure"];
  std::printf("figure 3.3 (%s): SH error %.3f, negative over %.1f%% of the hemisphere pairs; "
              "D-BRDF error %.3f, negative %.1f%%\n",
              o.figure_path.c_str(), f["sh_error_cosine_l2"].get<double>(),
              100 * f["sh_negative_fraction"].get<double>(), f["fit_error_cosine_l2"].get<double>(),
              100 * f["fit_negative_fraction"].get<double>());
  EXPECT_GT(f["sh_negative_fraction"].get<double>(), 0.0);
  EXPECT_EQ(f["fit_negative_fraction"].get<double>(), 0.0);
  EXPECT_LT(f["fit_error_cosine_l2"].get<double>(), f["sh_error_cosine_l2"].get<double>());
  EXPECT_GT(f["negative_pixel_fraction"]["sh"].get<double>(), 0.0);
  EXPECT_EQ(f["negative_pixel_fraction"]["fit"].get<double>(), 0.0);
  EXPECT_GT(std::filesystem::file_size(o.figure_path), 1000u);
}

TEST(FitSessionTest, SaturatedCaptureIsReportedNotFitted) {
  // Every pixel saturated (a 5 s exposure of a bright sample): the HDR merge drops them all.
  const std::string session = SimulatedSession("lambert:0.9", 2, {5e6, 1, "-saturated"});
  for (const char* model : {"dbrdf", "ggx"}) {
    const nlohmann::json r = FitSession(session, Options(model)).report;
    EXPECT_FALSE(r["fitted"].get<bool>()) << model;
    bool reported = false;
    for (const auto& c : r["conditions"]) reported = reported || c.get<std::string>().find("saturated") != std::string::npos;
    EXPECT_TRUE(reported) << r.dump(2);
  }
}

TEST(FitSessionTest, MirrorGivesAFiniteNarrowLobeAndNoErrors) {
  const std::string session = SimulatedSession("mirror:0.9", 4);
  const FitSessionOutcome d = FitSession(session, Options("dbrdf"));
  ASSERT_TRUE(d.report["fitted"].get<bool>());
  const Rgb c = RgbOf(d.report["params"]["c"]);
  EXPECT_TRUE(c.IsFinite());
  const std::string text = d.report["conditions"].dump();
  EXPECT_NE(text.find("narrow"), std::string::npos) << text;
  EXPECT_NE(d.report["warnings"].dump().find("delta"), std::string::npos);
  EXPECT_FALSE(d.report.contains("error_cosine_l2"));
  const FitSessionOutcome g = FitSession(session, Options("ggx"));
  EXPECT_TRUE(std::isfinite(g.report["params"]["alpha"].get<double>()));
}

// A copy of a shared session's measured files, so that fits written into it stay private.
std::string PrivateCopy(const std::string& session, const std::string& name) {
  const std::string dir = testing::TestBuildDir("test-fit-sessions") + "/" + name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  for (const char* f : {kSessionFile, kZonalFile, kReportFile}) {
    if (std::filesystem::exists(SessionPath(session, f))) {
      std::filesystem::copy_file(SessionPath(session, f), SessionPath(dir, f));
    }
  }
  return dir;
}

TEST(FitSessionTest, PriorFitLeavesTheMaterialOutAndWritesATableTheToolsRead) {
  const std::string dir =
      PrivateCopy(SimulatedSession("merl:gold-metallic-paint", 4), "prior-gold");
  FitSessionOptions o = Options("prior");
  o.write_outputs = true;
  o.prior.exclude = {"gold-metallic-paint"};
  const FitSessionOutcome outcome = FitSession(dir, o);
  const nlohmann::json& r = outcome.report;
  EXPECT_TRUE(r["fitted"].get<bool>());
  EXPECT_EQ(r["params"]["excluded"], nlohmann::json::array({"gold-metallic-paint"}));
  for (const auto& [channel, list] : r["params"]["contributions"].items()) {
    for (const auto& c : list) EXPECT_NE(c["material"], "gold-metallic-paint") << channel;
  }
  EXPECT_TRUE(r["uncertainty"]["available"].get<bool>());
  // Ngan et al.'s metric and the pooled one are both reported; a leave-one-out fit of this
  // glossy paint at order 4 is far from exact but nowhere near the blow-ups (10x and more) of
  // an unconstrained extrapolation: docs/accuracy.md has the population; 1.0 is what a black
  // BRDF would score.
  ASSERT_TRUE(r["error_ngan"]["hemisphere"].is_number());
  EXPECT_LT(r["error_ngan"]["hemisphere"].get<double>(), 1.0);
  EXPECT_LT(r["error_in_zone"].get<double>(), 0.5);
  // The table is what the session now hands to export, eval, preview and report.
  const BrdfFile file = ReadSessionBrdf(dir);
  EXPECT_EQ(file.kind, "tabulated-file");
  EXPECT_EQ(file.path, SessionPath(dir, kPriorFitFile));
  const auto* table = dynamic_cast<const TabulatedBrdf*>(file.brdf.get());
  ASSERT_NE(table, nullptr);
  EXPECT_FALSE(table->sigma().empty());
  // The file holds what the fit returned (float storage: 1e-7 relative).
  const Vec3 wi = SphericalDirection(0.5, 0.3), wo = SphericalDirection(0.6, 3.0);
  const Rgb a = table->Eval(wi, wo), b = outcome.model->Eval(wi, wo);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 1e-6 * (1 + b[c]));
}

TEST(FitSessionTest, AutoRecommendsTheBestPredictorAndSessionsHandItOn) {
  const std::string dir = PrivateCopy(SimulatedSession("lambert:0.5,0.4,0.3", 8), "auto-lambert");
  FitSessionOptions o = Options("auto");
  o.write_outputs = true;
  o.auto_candidates = {"prior", "ggx"};
  const FitSessionOutcome outcome = FitSession(dir, o);
  const nlohmann::json& choice = outcome.report["auto"];
  const std::string recommended = choice["recommended"].get<std::string>();
  double best = 1e300;
  std::string best_name;
  for (const auto& c : choice["candidates"]) {
    ASSERT_TRUE(c["cv_error"].is_number()) << c.dump();
    EXPECT_EQ(c["fold_errors"].size(), 4u);
    if (c["cv_error"].get<double>() < best) {
      best = c["cv_error"].get<double>();
      best_name = c["model"].get<std::string>();
    }
  }
  // The prior is preferred (fitting/model_selection.h): GGX replaces it only when it predicts
  // every block better and by the margin (25%).
  ASSERT_EQ(choice["candidates"][0]["model"], "prior");
  const nlohmann::json& prior = choice["candidates"][0];
  const nlohmann::json& ggx = choice["candidates"][1];
  bool every_block = true;
  for (int k = 0; k < 4; ++k) {
    every_block = every_block && ggx["fold_errors"][k].get<double>() <
                                     prior["fold_errors"][k].get<double>();
  }
  const bool replaced = every_block && ggx["cv_error"].get<double>() <=
                                           0.75 * prior["cv_error"].get<double>();
  EXPECT_EQ(recommended, replaced ? "ggx" : "prior") << choice.dump();
  if (recommended != best_name) {
    EXPECT_NE(choice["why"].get<std::string>().find("prior is kept"), std::string::npos);
  }
  EXPECT_EQ(outcome.report["model"], recommended);
  EXPECT_NE(choice["why"].get<std::string>().find(recommended), std::string::npos);
  // Both models explain a Lambertian: held-out coefficients are predicted to the capture's
  // own accuracy (0.84% in-zone error at order 4, docs/session-folder.md; 2% here at order 8).
  EXPECT_LT(best, 0.03);
  // fit-auto.json names the recommendation, and the session hands that file on.
  const std::string expected =
      recommended == "prior" ? SessionPath(dir, kPriorFitFile)
                             : SessionPath(dir, FitReportFileName(recommended));
  ASSERT_FALSE(SessionBrdfFiles(dir).empty());
  EXPECT_EQ(SessionBrdfFiles(dir).front(), expected);
  EXPECT_TRUE(std::filesystem::exists(SessionPath(dir, kAutoFitFile)));
  EXPECT_TRUE(std::filesystem::exists(SessionPath(dir, kPriorFitFile)));
  EXPECT_TRUE(std::filesystem::exists(SessionPath(dir, FitReportFileName("ggx"))));
}

TEST(FitSessionTest, RejectsUnknownModelsAndFoldersWithoutData) {
  EXPECT_THROW(FitSession(testing::TestBuildDir("test-sessions"), Options("phong")), InputError);
  EXPECT_THROW(FitSession(testing::TestBuildDir("test-empty-session"), Options("dbrdf")), InputError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
