#include "tools/fit_session.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include "acquisition/session.h"
#include "basis/atomic_file.h"
#include "basis/error.h"
#include "basis/hash.h"
#include "basis/option_checker.h"
#include "basis/stopwatch.h"
#include "brdf/brdf_prior.h"
#include "brdf/dbrdf_file.h"
#include "brdf/material_spec.h"
#include "brdf/sh_brdf.h"
#include "brdf/tabulated_file.h"
#include "fitting/model_selection.h"
#include "pictures/brdf_figure.h"
#include "rig/direction_maps.h"
#include "tools/sh_conversion.h"

namespace zbrdf {
namespace {

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

const PriorFitter& FitContext::Prior(const Zone& zone, int order, const std::string& prior_path,
                                     const PriorFitOptions& options, const std::string& cache_dir) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::shared_ptr<const BrdfPrior>& prior = priors_[prior_path];
  if (!prior) prior = std::make_shared<BrdfPrior>(ReadPriorFile(prior_path));
  auto& slot = prior_fitters_[{prior_path, {zone.theta_min_rad(), zone.theta_max_rad(), order}}];
  if (slot) return *slot;
  // The table projection depends on the grid, the zone, the order and the projection rule.
  const std::string dir = cache_dir.empty() ? DefaultCacheDir() + "/priors" : cache_dir;
  const double key_values[8] = {zone.theta_min_rad(), zone.theta_max_rad(), double(order),
                                options.projection.window_inner_deg,
                                options.projection.window_outer_deg,
                                double(options.projection.half_theta_per_piece),
                                double(options.projection.half_phi),
                                double(options.projection.pair.theta_nodes)};
  const int dims[3] = {prior->grid.theta_h_nodes(), prior->grid.theta_d_nodes(),
                       prior->grid.phi_d_nodes()};
  const uint64_t key = Fnv1a64(key_values, sizeof(key_values), Fnv1a64(dims, sizeof(dims)));
  char name[64];
  std::snprintf(name, sizeof(name), "projection-%016llx-v2.bin", static_cast<unsigned long long>(key));
  const std::string path = dir + "/" + name;
  const int rows = IsotropicLayout(order).size(), cols = prior->grid.size();
  Eigen::MatrixXf cached;
  {
    std::ifstream in(path, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const size_t payload = sizeof(float) * static_cast<size_t>(rows) * cols;
    // A damaged or foreign cache entry is rebuilt: payload, then its FNV-1a hash.
    if (bytes.size() == payload + sizeof(uint64_t)) {
      uint64_t stored;
      std::memcpy(&stored, bytes.data() + payload, sizeof(stored));
      if (stored == Fnv1a64(bytes.data(), payload)) {
        cached.resize(rows, cols);
        std::memcpy(cached.data(), bytes.data(), payload);
      }
    }
  }
  if (cached.size() > 0) {
    slot = std::make_unique<PriorFitter>(zone, order, prior, options, &cached);
  } else {
    slot = std::make_unique<PriorFitter>(zone, order, prior, options);
    const Eigen::MatrixXf& p = slot->TableProjection();
    std::string bytes(reinterpret_cast<const char*>(p.data()), sizeof(float) * p.size());
    const uint64_t hash = Fnv1a64(bytes);
    bytes.append(reinterpret_cast<const char*>(&hash), sizeof(hash));
    try {
      std::filesystem::create_directories(dir);
      WriteFileAtomically(path, bytes);
    } catch (const std::exception&) {
      // A cache that cannot be written costs time, not results.
    }
  }
  return *slot;
}

void FitSessionOptions::Validate() const {
  OptionChecker check("FitSessionOptions");
  const auto known = [](const std::string& m) {
    return m == "prior" || m == "dbrdf" || m == "ggx" || m == "ward" || m == "as";
  };
  check.Require(known(model) || model == "auto", "model",
                "must be prior, auto, dbrdf, ggx, ward or as (got '" + model + "')")
      .InRange("auto_folds", auto_folds, 2, 16)
      .InRangeBelow("auto_margin", auto_margin, 0, 1);
  for (const std::string& c : auto_candidates) {
    check.Require(known(c), "auto_candidates",
                  "must name prior, dbrdf, ggx, ward or as (got '" + c + "')");
  }
  check.Require(!auto_candidates.empty(), "auto_candidates", "must name at least one model")
      .Nested("dbrdf", dbrdf)
      .Nested("analytic", analytic)
      .Nested("prior", prior)
      .Nested("comparison", comparison)
      .ThrowIfInvalid();
}

namespace {

// One model fitted to the whole tensor: its report entries (model, params, residual, ...) and
// the BRDF.
struct SingleFit {
  nlohmann::json report;
  std::shared_ptr<const Brdf> model;
};

const PriorFitter& PriorFitterFor(const ZonalTensor& data, const FitSessionOptions& options,
                                  FitContext& fits) {
  const std::string path = options.prior_path.empty() ? DefaultPriorPath() : options.prior_path;
  return fits.Prior(data.zone(), data.order, path, options.prior, options.cache_dir);
}

SingleFit FitModel(const std::string& model_name, const ZonalTensor& data,
                   const FitSessionOptions& options, FitContext& fits) {
  SingleFit out;
  nlohmann::json& report = out.report;
  report["model"] = model_name;
  const auto t0 = WallClock::now();
  if (model_name == "prior") {
    const PriorFitter& fitter = PriorFitterFor(data, options, fits);
    const double precompute = SecondsSince(t0);
    const PriorFitResult fit = fitter.Fit(data, options.prior);
    report["fit_time_s"] = SecondsSince(t0);
    report["fit_time_breakdown"] = {{"precompute_s", precompute}, {"solve_s", fit.solve_seconds}};
    report["params"] = fit.ToJson();
    report["params"]["prior"] = options.prior_path.empty() ? DefaultPriorPath() : options.prior_path;
    report["params"]["grid"] = fitter.prior().grid.ToString();
    report["params"]["model_error_floor"] = options.prior.model_error_floor;
    report["uncertainty"] = {{"available", !fit.brdf->sigma().empty()},
                             {"relative_hemisphere", fit.relative_uncertainty_hemisphere},
                             {"relative_zone", fit.relative_uncertainty_zone}};
    report["isotropic"] = true;
    report["residual"] = StatisticsJson(fit.statistics);
    report["fitted"] = fit.fitted;
    report["conditions"] = fit.conditions;
    out.model = fit.brdf;
  } else if (model_name == "dbrdf") {
    const DBrdfFitter& fitter = fits.DBrdf(data.zone(), data.order, options.dbrdf);
    const double precompute = SecondsSince(t0);
    const DBrdfFitResult fit = fitter.Fit(data);
    report["fit_time_s"] = SecondsSince(t0);
    report["fit_time_breakdown"] = {{"precompute_s", precompute}, {"solve_s", fit.solve_seconds}};
    report["params"] = fit.ToJson();
    report["uncertainty"] = report["params"]["uncertainty"];
    report["isotropic"] = fit.isotropic_table;
    report["residual"] = StatisticsJson(fit.statistics);
    report["fitted"] = fit.fitted;
    report["conditions"] = fit.conditions;
    out.model = std::make_shared<DBrdf>(fit.params);
  } else {
    const AnalyticFitter& fitter = fits.Analytic(data.zone(), data.order, options.analytic);
    const double precompute = SecondsSince(t0);
    const AnalyticFitResult fit = fitter.Fit(data, ParseAnalyticModel(model_name));
    report["fit_time_s"] = SecondsSince(t0);
    report["fit_time_breakdown"] = {{"precompute_s", precompute + fit.precompute_seconds},
                                    {"solve_s", fit.solve_seconds}};
    report["params"] = fit.ToJson();
    report["uncertainty"] = report["params"]["uncertainty"];
    report["spec"] = fit.spec;
    report["isotropic"] = fit.isotropy.isotropic;
    report["residual"] = StatisticsJson(fit.statistics);
    report["fitted"] = fit.fitted;
    report["conditions"] = fit.conditions;
    out.model = fit.brdf;
  }
  return out;
}

// A candidate of --model auto: fits the training tensor, predicts its isotropic coefficients
// with the model's own forward projection.
ModelCandidate MakeCandidate(const std::string& name, const FitSessionOptions& options,
                             FitContext& fits) {
  return {name, [name, &options, &fits](const ZonalTensor& train) {
            if (name == "prior") {
              PriorFitOptions quick = options.prior;
              quick.replicates = 0;  // the uncertainty is not needed to predict
              return PriorFitterFor(train, options, fits).Fit(train, quick).model;
            }
            const SingleFit fit = FitModel(name, train, options, fits);
            const PairQuadrature& q =
                name == "dbrdf"
                    ? fits.DBrdf(train.zone(), train.order, options.dbrdf).quadrature()
                    : fits.Analytic(train.zone(), train.order, options.analytic).quadrature();
            return q.ProjectIsotropicBrdf(*fit.model);
          }};
}

// Errors of a fit against the session's true material (report keys error_*).
void CompareWithTruth(const Brdf& model, const Brdf& truth, const Zone& zone,
                      const BrdfComparisonOptions& options, nlohmann::json* report) {
  const auto t_err = WallClock::now();
  const BrdfComparison c = CompareBrdfs(model, truth, zone, options);
  (*report)["material"] = truth.Spec();
  (*report)["error_cosine_l2"] = Finite(c.cosine_l2);
  (*report)["error_cosine_l2_80"] = Finite(c.cosine_l2_80);
  (*report)["error_in_zone"] = Finite(c.in_zone);
  (*report)["error_outside_zone"] = c.has_outside ? Finite(c.outside_zone) : nlohmann::json(nullptr);
  (*report)["error_ngan"] = {{"hemisphere", Finite(c.cosine_l2_channel_mean)},
                             {"theta_80", Finite(c.cosine_l2_80_channel_mean)},
                             {"zone", Finite(c.in_zone_channel_mean)}};
  (*report)["error_time_s"] = SecondsSince(t_err);
}

// Writes fit-<model>.json and the model's file (fit-dbrdf.exr, fit-prior.exr) into the session.
void WriteFitOutputs(const std::string& session_dir, const std::string& model_name,
                     const Brdf& model, nlohmann::json* report) {
  nlohmann::json outputs = nlohmann::json::object();
  const std::string json_path = SessionPath(session_dir, FitReportFileName(model_name));
  if (model_name == "dbrdf") outputs["dbrdf"] = SessionPath(session_dir, kDBrdfFitFile);
  if (model_name == "prior") {
    outputs["table"] = SessionPath(session_dir, kPriorFitFile);
    // The report names the table as its model, so that the report itself reads as this fit.
    (*report)["spec"] = "file:" + SessionPath(session_dir, kPriorFitFile);
  }
  outputs["report"] = json_path;
  (*report)["outputs"] = outputs;
  if (model_name == "dbrdf") {
    WriteDBrdfFile(SessionPath(session_dir, kDBrdfFitFile), static_cast<const DBrdf&>(model),
                   *report);
  } else if (model_name == "prior") {
    WriteTabulatedFile(SessionPath(session_dir, kPriorFitFile),
                       static_cast<const TabulatedBrdf&>(model), *report);
  }
  WriteFileAtomically(json_path, report->dump(2) + "\n");
}

}  // namespace

FitSessionOutcome FitSession(const std::string& session_dir, const FitSessionOptions& options,
                             FitContext* context) {
  options.Validate();
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
  if (options.compare || !options.figure_path.empty()) outcome.truth = SessionMaterial(session_dir);
  const bool compare = outcome.truth && options.compare && !outcome.truth->IsDelta();

  // --model auto: cross-validate the candidates, then fit each to all the data.
  std::string model_name = options.model;
  nlohmann::json auto_report;
  std::map<std::string, SingleFit> candidates_fitted;
  if (model_name == "auto") {
    const auto t_select = WallClock::now();
    std::vector<ModelCandidate> candidates;
    for (const std::string& name : options.auto_candidates) {
      candidates.push_back(MakeCandidate(name, options, fits));
    }
    ModelSelectionOptions selection_options;
    selection_options.folds = options.auto_folds;
    selection_options.margin = options.auto_margin;
    // The prior is preferred: its extrapolation is bounded by measured materials
    // (fitting/model_selection.h).
    if (std::find(options.auto_candidates.begin(), options.auto_candidates.end(), "prior") !=
        options.auto_candidates.end()) {
      selection_options.preferred = "prior";
    }
    const ModelSelection selection = SelectModel(data, candidates, selection_options);
    if (selection.recommended.empty()) {
      throw InputError("zbrdf fit --model auto: no candidate could be fitted to " + session_dir +
                       " (" + selection.ToJson().dump() + ")");
    }
    auto_report = selection.ToJson();
    auto_report["selection_time_s"] = SecondsSince(t_select);
    model_name = selection.recommended;
    nlohmann::json errors = nlohmann::json::object();
    for (const std::string& name : options.auto_candidates) {
      SingleFit fit = FitModel(name, data, options, fits);
      fit.report["session"] = session_dir;
      fit.report["order"] = data.order;
      fit.report["zone_deg"] = {RadToDeg(data.theta_min_rad), RadToDeg(data.theta_max_rad)};
      if (compare) {
        CompareWithTruth(*fit.model, *outcome.truth, data.zone(), options.comparison, &fit.report);
        errors[name] = {{"error_cosine_l2", fit.report["error_cosine_l2"]},
                        {"error_cosine_l2_80", fit.report["error_cosine_l2_80"]},
                        {"error_in_zone", fit.report["error_in_zone"]},
                        {"error_ngan", fit.report["error_ngan"]}};
      }
      if (options.write_outputs && name != model_name) {
        fit.report["warnings"] = nlohmann::json::array();
        WriteFitOutputs(session_dir, name, *fit.model, &fit.report);
      }
      candidates_fitted.emplace(name, std::move(fit));
    }
    if (!errors.empty()) auto_report["errors_against_truth"] = errors;
    if (model_name == "prior") {
      const nlohmann::json& u = candidates_fitted["prior"].report["uncertainty"];
      const double spread = u.value("relative_hemisphere", 0.0);
      char line[200];
      std::snprintf(line, sizeof(line),
                    "; outside the zone its one-sigma uncertainty is %.0f%% of the BRDF "
                    "(cosine-weighted), %.0f%% inside",
                    100 * spread, 100 * u.value("relative_zone", 0.0));
      auto_report["why"] = auto_report["why"].get<std::string>() + line;
    } else {
      auto_report["why"] = auto_report["why"].get<std::string>() +
                           "; an analytic lobe extrapolates outside the zone by its formula only";
    }
  }

  SingleFit single = candidates_fitted.count(model_name)
                         ? std::move(candidates_fitted[model_name])
                         : FitModel(model_name, data, options, fits);
  nlohmann::json& report = outcome.report;
  report = std::move(single.report);
  outcome.model = single.model;
  report["session"] = session_dir;
  report["order"] = data.order;
  report["zone_deg"] = {RadToDeg(data.theta_min_rad), RadToDeg(data.theta_max_rad)};
  if (!auto_report.is_null()) report["auto"] = auto_report;

  std::vector<std::string> warnings;
  if (outcome.truth && options.compare && outcome.truth->IsDelta()) {
    report["material"] = outcome.truth->Spec();
    warnings.push_back("the true material is a delta (perfect mirror): its f_r is a distribution, "
                       "so the L2 errors are undefined and not reported");
  } else if (compare && !report.contains("error_cosine_l2")) {
    CompareWithTruth(*outcome.model, *outcome.truth, data.zone(), options.comparison, &report);
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
    WriteFitOutputs(session_dir, model_name, *outcome.model, &report);
    if (report.contains("auto")) {
      nlohmann::json choice = report["auto"];
      choice["session"] = session_dir;
      choice["report"] = SessionPath(session_dir, FitReportFileName(model_name));
      WriteFileAtomically(SessionPath(session_dir, kAutoFitFile), choice.dump(2) + "\n");
      report["outputs"]["auto"] = SessionPath(session_dir, kAutoFitFile);
    }
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
  if (r.contains("auto") && r["auto"].is_object()) {
    const nlohmann::json& a = r["auto"];
    out << "  auto: recommends " << a.value("recommended", std::string()) << ": "
        << a.value("why", std::string()) << "\n";
  }
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
