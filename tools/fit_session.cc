#include "tools/fit_session.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "acquisition/session.h"
#include "basis/atomic_file.h"
#include "basis/error.h"
#include "basis/option_checker.h"
#include "brdf/dbrdf_file.h"
#include "brdf/material_spec.h"
#include "brdf/sh_brdf.h"
#include "pictures/brdf_figure.h"
#include "tools/sh_conversion.h"

namespace zbrdf {
namespace {

using WallClock = std::chrono::steady_clock;
double Since(WallClock::time_point t) { return std::chrono::duration<double>(WallClock::now() - t).count(); }

nlohmann::json Finite(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json StatisticsJson(const FitStatistics& s) {
  return {{"chi2", Finite(s.chi2)},
          {"chi2_per_dof", Finite(s.chi2_per_dof)},
          {"relative_residual", Finite(s.relative_residual)},
          {"residuals", s.residuals},
          {"parameters", s.parameters},
          {"iterations", s.iterations},
          {"termination", s.termination}};
}

}  // namespace

ZonalTensor ToZonalTensor(const ZonalData& data) {
  ZonalTensor t;
  t.theta_min_rad = data.theta_min_rad;
  t.theta_max_rad = data.theta_max_rad;
  t.order = data.order;
  t.z = data.tensor;
  t.variance = data.tensor_variance;
  return t;
}

std::shared_ptr<const Brdf> SessionMaterial(const std::string& session_dir) {
  const nlohmann::json s = SessionFolder::Open(session_dir).session();
  const std::string material = s.value("material", std::string());
  if (material.empty()) return nullptr;
  return MakeBrdf(material);
}

const DBrdfFitter& FitContext::DBrdf(const Zone& zone, int order, const DBrdfFitOptions& options) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto& slot = dbrdf_[{zone.theta_min_rad(), zone.theta_max_rad(), order}];
  if (!slot) slot = std::make_unique<DBrdfFitter>(zone, order, options);
  return *slot;
}

const AnalyticFitter& FitContext::Analytic(const Zone& zone, int order,
                                           const AnalyticFitOptions& options) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto& slot = analytic_[{zone.theta_min_rad(), zone.theta_max_rad(), order}];
  if (!slot) slot = std::make_unique<AnalyticFitter>(zone, order, options);
  return *slot;
}

void FitSessionOptions::Validate() const {
  OptionChecker check("FitSessionOptions");
  check.Require(model == "dbrdf" || model == "ggx" || model == "ward" || model == "as", "model",
                "must be dbrdf, ggx, ward or as (got '" + model + "')")
      .Nested("dbrdf", dbrdf)
      .Nested("analytic", analytic)
      .Nested("comparison", comparison)
      .ThrowIfInvalid();
}

FitSessionOutcome FitSession(const std::string& session_dir, const FitSessionOptions& options,
                             FitContext* context) {
  options.Validate();
  const std::string& model_name = options.model;
  const std::string zonal_path = SessionPath(session_dir, kZonalFile);
  if (!std::filesystem::exists(zonal_path)) {
    throw InputError(session_dir + " has no zonal.exr; capture or simulate the session first "
                     "(zbrdf simulate / zbrdf capture), or process it (zbrdf process)");
  }
  const ZonalData zonal = ReadZonalExr(zonal_path);
  const ZonalTensor data = ToZonalTensor(zonal);
  FitContext local;
  FitContext& fits = context ? *context : local;
  FitSessionOutcome outcome;
  nlohmann::json& report = outcome.report;
  report["model"] = model_name;
  report["session"] = session_dir;
  report["order"] = data.order;
  report["zone_deg"] = {RadToDeg(data.theta_min_rad), RadToDeg(data.theta_max_rad)};
  std::vector<std::string> conditions;
  const auto t0 = WallClock::now();
  if (model_name == "dbrdf") {
    const auto t_pre = WallClock::now();
    const DBrdfFitter& fitter = fits.DBrdf(data.zone(), data.order, options.dbrdf);
    const double precompute = Since(t_pre);
    const DBrdfFitResult fit = fitter.Fit(data);
    report["fit_time_s"] = Since(t0);
    report["fit_time_breakdown"] = {{"precompute_s", precompute}, {"solve_s", fit.solve_seconds}};
    report["params"] = fit.ToJson();
    report["uncertainty"] = report["params"]["uncertainty"];
    report["isotropic"] = fit.isotropic_table;
    report["residual"] = StatisticsJson(fit.statistics);
    report["fitted"] = fit.fitted;
    conditions = fit.conditions;
    outcome.model = std::make_shared<DBrdf>(fit.params);
  } else {
    const auto t_pre = WallClock::now();
    const AnalyticFitter& fitter = fits.Analytic(data.zone(), data.order, options.analytic);
    const double precompute = Since(t_pre);
    const AnalyticFitResult fit = fitter.Fit(data, ParseAnalyticModel(model_name));
    report["fit_time_s"] = Since(t0);
    report["fit_time_breakdown"] = {{"precompute_s", precompute + fit.precompute_seconds},
                                    {"solve_s", fit.solve_seconds}};
    report["params"] = fit.ToJson();
    report["uncertainty"] = report["params"]["uncertainty"];
    report["spec"] = fit.spec;
    report["isotropic"] = fit.isotropy.isotropic;
    report["residual"] = StatisticsJson(fit.statistics);
    report["fitted"] = fit.fitted;
    conditions = fit.conditions;
    outcome.model = fit.brdf;
  }
  report["conditions"] = conditions;

  // Errors against the truth.
  if (options.compare || !options.figure_path.empty()) outcome.truth = SessionMaterial(session_dir);
  std::vector<std::string> warnings;
  if (outcome.truth && options.compare && outcome.truth->IsDelta()) {
    report["material"] = outcome.truth->Spec();
    warnings.push_back("the true material is a delta (perfect mirror): its f_r is a distribution, "
                       "so the L2 errors are undefined and not reported");
  } else if (outcome.truth && options.compare) {
    const auto t_err = WallClock::now();
    const BrdfComparison c = CompareBrdfs(*outcome.model, *outcome.truth, data.zone(), options.comparison);
    report["material"] = outcome.truth->Spec();
    report["error_cosine_l2"] = Finite(c.cosine_l2);
    report["error_cosine_l2_80"] = Finite(c.cosine_l2_80);
    report["error_in_zone"] = Finite(c.in_zone);
    report["error_outside_zone"] = c.has_outside ? Finite(c.outside_zone) : nlohmann::json(nullptr);
    report["error_time_s"] = Since(t_err);
  }
  if (!options.figure_path.empty()) {
    if (!outcome.truth) {
      throw InputError("--figure needs a simulated session (session.json names the material) to "
                       "show the ground truth");
    }
    ShConversionOptions sh_options;
    const ShConversionResult sh = ConvertToSh(data, sh_options);
    const ShBrdf sh_brdf(sh.data);
    const CosineWeightedFn sh_fn = [&sh_brdf](const Vec3& w_o, std::span<const Vec3> w_i, std::span<Rgb> out) {
      sh_brdf.CosineWeightedBatch(w_o, w_i, out);
    };
    const BrdfComparison sh_error = CompareBrdfs(sh_fn, CosineWeightedOf(*outcome.truth), data.zone(), options.comparison);
    const BrdfComparison fit_error = CompareBrdfs(CosineWeightedOf(*outcome.model), CosineWeightedOf(*outcome.truth),
                                                  data.zone(), options.comparison);
    char sh_label[64], fit_label[64];
    std::snprintf(sh_label, sizeof(sh_label), "SH order %d (zonal data)", sh.data.order);
    std::snprintf(fit_label, sizeof(fit_label), "%s fit", model_name == "dbrdf" ? "D-BRDF" : model_name.c_str());
    const FigureStats stats = WriteSphereFigure(
        options.figure_path, {{"ground truth", CosineWeightedOf(*outcome.truth)},
                              {sh_label, sh_fn},
                              {fit_label, CosineWeightedOf(*outcome.model)}});
    report["figure"] = {{"path", options.figure_path},
                        {"sh_error_cosine_l2", Finite(sh_error.cosine_l2)},
                        {"sh_error_in_zone", Finite(sh_error.in_zone)},
                        {"sh_negative_fraction", sh_error.negative_fraction},
                        {"fit_error_cosine_l2", Finite(fit_error.cosine_l2)},
                        {"fit_negative_fraction", fit_error.negative_fraction},
                        {"negative_pixel_fraction",
                         {{"truth", stats.negative_pixel_fraction[0]},
                          {"sh", stats.negative_pixel_fraction[1]},
                          {"fit", stats.negative_pixel_fraction[2]}}}};
  }
  if (!report.value("fitted", false)) warnings.push_back("nothing was fitted: see conditions");
  report["warnings"] = warnings;
  if (options.write_outputs) {
    nlohmann::json outputs = nlohmann::json::object();
    const std::string json_path = SessionPath(session_dir, FitReportFileName(model_name));
    if (model_name == "dbrdf") {
      const std::string exr_path = SessionPath(session_dir, kDBrdfFitFile);
      outputs["dbrdf"] = exr_path;
      report["outputs"] = outputs;
      WriteDBrdfFile(exr_path, static_cast<const DBrdf&>(*outcome.model), report);
    }
    outputs["report"] = json_path;
    report["outputs"] = outputs;
    WriteFileAtomically(json_path, report.dump(2) + "\n");
  }
  return outcome;
}

std::string FormatFitSummary(const nlohmann::json& r) {
  std::ostringstream out;
  char line[400];
  std::snprintf(line, sizeof(line), "%s fit of %s (order %d, zone %.1f-%.1f deg) in %.2f s\n",
                r.value("model", std::string()).c_str(), r.value("session", std::string()).c_str(),
                r.value("order", 0), r["zone_deg"][0].get<double>(), r["zone_deg"][1].get<double>(),
                r.value("fit_time_s", 0.0));
  out << line;
  const nlohmann::json& p = r["params"];
  if (r.value("model", std::string()) == "dbrdf") {
    std::snprintf(line, sizeof(line),
                  "  c = (%.4g, %.4g, %.4g)  F0 = %.4g  kd = (%.4g, %.4g, %.4g)\n"
                  "  table: %s, %d x %d; alpha-equivalent %.4g; tail GGX alpha %.4g\n",
                  p["c"][0].get<double>(), p["c"][1].get<double>(), p["c"][2].get<double>(),
                  p["F0"].get<double>(), p["kd"][0].get<double>(), p["kd"][1].get<double>(),
                  p["kd"][2].get<double>(), p["table"].get<std::string>().c_str(),
                  p["theta_samples"].get<int>(), p["phi_samples"].get<int>(),
                  p["alpha_equivalent"].get<double>(), p["tail_alpha"].get<double>());
    out << line;
  } else {
    out << "  " << r.value("spec", std::string()) << "\n";
  }
  const nlohmann::json& u = r["uncertainty"];
  if (u.value("available", false)) {
    out << "  uncertainty (1 sigma): " << u.dump() << "\n";
  }
  const nlohmann::json& res = r["residual"];
  if (!res["chi2_per_dof"].is_null()) {
    std::snprintf(line, sizeof(line), "  residual: chi2/dof %.3g, relative %.3g%% (%d coefficients, %d iterations)\n",
                  res["chi2_per_dof"].get<double>(), 100 * res["relative_residual"].get<double>(),
                  res["residuals"].get<int>(), res["iterations"].get<int>());
    out << line;
  }
  if (r.contains("error_cosine_l2") && !r["error_cosine_l2"].is_null()) {
    std::snprintf(line, sizeof(line),
                  "  error vs %s: cosine-weighted L2 %.2f%% (hemisphere), %.2f%% in the zone",
                  r["material"].get<std::string>().c_str(), 100 * r["error_cosine_l2"].get<double>(),
                  100 * r["error_in_zone"].get<double>());
    out << line;
    if (!r["error_outside_zone"].is_null()) {
      std::snprintf(line, sizeof(line), ", %.2f%% outside", 100 * r["error_outside_zone"].get<double>());
      out << line;
    }
    out << "\n";
  }
  if (r.contains("figure")) {
    const nlohmann::json& f = r["figure"];
    std::snprintf(line, sizeof(line),
                  "  figure %s: SH error %.2f%%, negative over %.2f%% of the hemisphere pairs; fit "
                  "error %.2f%%, negative %.2f%%\n",
                  f["path"].get<std::string>().c_str(), 100 * f["sh_error_cosine_l2"].get<double>(),
                  100 * f["sh_negative_fraction"].get<double>(),
                  100 * f["fit_error_cosine_l2"].get<double>(),
                  100 * f["fit_negative_fraction"].get<double>());
    out << line;
  }
  for (const auto& c : r["conditions"]) out << "  note: " << c.get<std::string>() << "\n";
  for (const auto& w : r["warnings"]) out << "  warning: " << w.get<std::string>() << "\n";
  if (r.contains("outputs")) {
    for (const auto& [key, value] : r["outputs"].items()) out << "  wrote " << value.get<std::string>() << "\n";
  }
  return out.str();
}

}  // namespace zbrdf
