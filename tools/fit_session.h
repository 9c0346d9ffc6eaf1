// Fitting a session folder's zonal data: what `zbrdf fit` and `zbrdf fit-all` run.
//
// Reads SESSION/zonal.exr, fits the model (dbrdf, ggx, ward or as; fitting/dbrdf_fit.h,
// fitting/analytic_fit.h), and for simulated sessions (session.json "material") compares the fit
// with the true material (fitting/fit_error.h). Writes into the session folder:
//   fit-dbrdf.exr   the D-BRDF (brdf/dbrdf_file.h), the report in its zbrdf.info attribute
//   fit-<model>.json  the report; for analytic models its "spec" is a material spec
//                     (brdf/material_spec.h) that recreates the fitted BRDF
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

 private:
  using Key = std::tuple<double, double, int>;
  std::mutex mutex_;
  std::map<Key, std::unique_ptr<DBrdfFitter>> dbrdf_;
  std::map<Key, std::unique_ptr<AnalyticFitter>> analytic_;
};

struct FitSessionOptions {
  std::string model = "dbrdf";  // dbrdf, ggx, ward, as
  bool write_outputs = true;
  bool compare = true;          // errors against session.json's material, when there is one
  std::string figure_path;      // PNG: truth | SH (order of the data) | fit; needs a material
  DBrdfFitOptions dbrdf;
  AnalyticFitOptions analytic;
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
FitSessionOutcome FitSession(const std::string& session_dir, const FitSessionOptions& options,
                             FitContext* context = nullptr);

// A few human-readable lines of a fit report.
std::string FormatFitSummary(const nlohmann::json& report);

}  // namespace zbrdf
