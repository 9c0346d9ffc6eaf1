// Fitting a session folder's zonal data: what `zbrdf fit` and `zbrdf fit-all` run.
//
// Reads SESSION/zonal.exr, fits the model (prior, dbrdf, ggx, ward or as; fitting/prior_fit.h,
// fitting/dbrdf_fit.h, fitting/analytic_fit.h) or chooses one (auto: tools/model_selection.h),
// and for simulated sessions (session.json "material") compares the fit with the true material
// (fitting/fit_error.h). Writes into the session folder:
//   fit-prior.exr   the prior's whole-hemisphere table with its uncertainty
//                   (brdf/tabulated_file.h), the report in its zbrdf.info attribute
//   fit-dbrdf.exr   the D-BRDF (brdf/dbrdf_file.h), the report in its zbrdf.info attribute
//   fit-<model>.json  the report; for analytic models its "spec" is a material spec
//                     (brdf/material_spec.h) that recreates the fitted BRDF
//   fit-auto.json   for auto: every candidate's cross-validated error, the recommendation and why
// The report's keys: model, params, spec (analytic), fit_time_s, fit_time_breakdown,
// isotropic, residual, conditions, warnings, outputs, session, order, zone_deg, and for simulated
// sessions material, error_cosine_l2, error_in_zone, error_outside_zone.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>

#include <nlohmann/json.hpp>

#include "acquisition/zonal.h"
#include "brdf/brdf.h"
#include "fitting/analytic_fit.h"
#include "fitting/dbrdf_fit.h"
#include "fitting/fit_data.h"
#include "fitting/fit_error.h"
#include "fitting/prior_fit.h"

namespace zbrdf {

// The fitting layer's view of a session's zonal data (tensor and variances).
ZonalTensor ToZonalTensor(const ZonalData& data);

// The true material of a simulated session (session.json "material"), or null for a measured
// one. Throws InputError if the spec cannot be built.
std::shared_ptr<const Brdf> SessionMaterial(const std::string& session_dir);

// Fitters reused across sessions with the same zone and order (their precomputation is most of
// a fit's time). Thread-safe.
class FitContext {
 public:
  const DBrdfFitter& DBrdf(const Zone& zone, int order, const DBrdfFitOptions& options);
  const AnalyticFitter& Analytic(const Zone& zone, int order, const AnalyticFitOptions& options);
  // The prior file is read once per path; the projection of its grid for (zone, order) is loaded
  // from or stored in the cache folder (empty: DefaultCacheDir()/priors), keyed by grid, zone,
  // order and projection rule.
  const PriorFitter& Prior(const Zone& zone, int order, const std::string& prior_path,
                           const PriorFitOptions& options, const std::string& cache_dir = "");

 private:
  using Key = std::tuple<double, double, int>;
  std::mutex mutex_;
  std::map<Key, std::unique_ptr<DBrdfFitter>> dbrdf_;
  std::map<Key, std::unique_ptr<AnalyticFitter>> analytic_;
  std::map<std::string, std::shared_ptr<const BrdfPrior>> priors_;
  std::map<std::pair<std::string, Key>, std::unique_ptr<PriorFitter>> prior_fitters_;
};

struct FitSessionOptions {
  std::string model = "dbrdf";  // prior, auto, dbrdf, ggx, ward, as
  std::string prior_path;       // empty: DefaultPriorPath() (brdf/brdf_prior.h)
  std::string cache_dir;        // prior projections; empty: DefaultCacheDir()/priors
  // auto: the candidates cross-validated (tools/model_selection.h)
  std::vector<std::string> auto_candidates{"prior", "dbrdf", "ggx"};
  int auto_folds = 4;
  // How much lower (relative) another candidate's cross-validated error must be, in every
  // block, to be recommended over the prior (fitting/model_selection.h).
  double auto_margin = 0.25;
  bool write_outputs = true;
  bool compare = true;          // errors against session.json's material, when there is one
  std::string figure_path;      // PNG: truth | SH (order of the data) | fit; needs a material
  DBrdfFitOptions dbrdf;
  AnalyticFitOptions analytic;
  PriorFitOptions prior;
  BrdfComparisonOptions comparison;

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

struct FitSessionOutcome {
  nlohmann::json report;
  std::shared_ptr<const Brdf> model;  // the fitted BRDF
  std::shared_ptr<const Brdf> truth;  // the session's material, or null
};

// Throws InputError for an unknown model, a folder without zonal.exr, or an unreadable file.
// For auto, the outcome is the recommended model's, with report["auto"] holding the choice.
FitSessionOutcome FitSession(const std::string& session_dir, const FitSessionOptions& options,
                             FitContext* context = nullptr);

// A few human-readable lines of a fit report.
std::string FormatFitSummary(const nlohmann::json& report);

}  // namespace zbrdf
