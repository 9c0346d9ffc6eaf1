// zbrdf fit: a renderable BRDF model fitted to a session's zonal coefficients.
#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "basis/error.h"
#include "tools/cli/command.h"
#include "tools/fit_session.h"

namespace zbrdf::cli {
namespace {

int RunFit(const std::vector<std::string>& args) {
  CommandLine cl("fit",
                 "Fits a BRDF model to a session's zonal coefficients (zonal.exr), in coefficient\n"
                 "space, weighted by the coefficients' variances (docs/fitting.md, docs/prior.md):\n"
                 "  prior  whole-hemisphere table: a non-negative combination of the measured\n"
                 "         materials of a prior (default: the 100 MERL materials), with a\n"
                 "         per-direction uncertainty; writes fit-prior.exr\n"
                 "  auto   cross-validates prior, dbrdf and ggx on blocks of the zonal tensor,\n"
                 "         recommends the one that predicts held-out coefficients best, says\n"
                 "         why (fit-auto.json); export, preview and report use it\n"
                 "  dbrdf  distribution-based BRDF (Ashikhmin & Premoze 2007): tabulated p(h),\n"
                 "         1-D for isotropic data, 2-D for anisotropic ones, c, F0, kd\n"
                 "  ggx    GGX microfacet model with Smith shadowing, F0 (RGB), kd (RGB)\n"
                 "  ward   Ward's model, rho_s, rho_d (RGB)\n"
                 "  as     Ashikhmin-Shirley, Rs, Rd (RGB)\n"
                 "Writes fit-<model>.json (and fit-dbrdf.exr for the D-BRDF) into the session.");
  cl.Positional("SESSION", "session folder holding zonal.exr")
      .Option("model", "M", "auto, prior, dbrdf, ggx, ward or as", "dbrdf")
      .Option("prior", "FILE", "prior for --model prior/auto (default: data/priors/merl100.exr)")
      .Option("exclude", "NAMES", "prior materials to leave out, comma-separated (leave-one-out)")
      .Option("candidates", "LIST", "models --model auto compares", "prior,dbrdf,ggx")
      .Option("replicates", "N", "prior: refits for the per-direction uncertainty", "8")
      .Option("model-error", "F", "prior: error floor relative to the coefficients' RMS", "0.01")
      .Option("table", "T", "D-BRDF table: auto (from the data's isotropy), 1d or 2d", "auto")
      .Option("f0-range", "MIN,MAX", "D-BRDF: bounds of F0 (equal values fix it)", "0.04,1")
      .Option("figure", "FILE.png", "render ground truth | SH | fit side by side (simulated sessions)")
      .Flag("no-write", "do not write fit-<model>.* into the session")
      .Flag("no-compare", "skip the comparison with a simulated session's true material")
      .Flag("json", "print the report as one JSON object")
      .Epilog("Examples:\n"
              "  zbrdf fit results/blue-acrylic --model auto\n"
              "  zbrdf fit results/blue-acrylic --model dbrdf --figure figure-3-3.png\n\n"
              "JSON keys: model, params, spec (analytic models), fit_time_s, fit_time_breakdown,\n"
              "isotropic, residual, uncertainty, conditions, warnings, outputs; for simulated\n"
              "sessions material, error_cosine_l2 (Ngan et al. 2005, hemisphere, relative),\n"
              "error_cosine_l2_80, error_in_zone, error_outside_zone, error_ngan (the same per\n"
              "channel, averaged); with --figure, figure; with --model auto, auto\n"
              "(recommended, why, candidates with cv_error).");
  if (!cl.Parse(args)) return 0;
  FitSessionOptions options;
  options.model = cl.Get("model");
  const std::string table = cl.Get("table");
  if (table == "1d") {
    options.dbrdf.table = DBrdfFitOptions::Table::kIsotropic;
  } else if (table == "2d") {
    options.dbrdf.table = DBrdfFitOptions::Table::kAnisotropic;
  } else if (table != "auto") {
    throw InputError("--table must be auto, 1d or 2d (got " + table + ")");
  }
  const std::vector<double> f0 = cl.GetDoubles("f0-range", 2);
  options.dbrdf.f0_min = f0[0];
  options.dbrdf.f0_max = f0[1];
  if (cl.Has("prior")) options.prior_path = cl.Get("prior");
  if (cl.Has("exclude")) options.prior.exclude = cl.GetList("exclude");
  options.auto_candidates = cl.GetList("candidates");
  options.prior.replicates = cl.GetInt("replicates", 0, 256);
  options.prior.model_error_floor = cl.GetDouble("model-error", 0.0, 1.0);
  options.write_outputs = !cl.Has("no-write");
  options.compare = !cl.Has("no-compare");
  if (cl.Has("figure")) options.figure_path = cl.Get("figure");
  const FitSessionOutcome outcome = FitSession(cl.Positional(0), options);
  if (cl.Has("json")) {
    std::cout << outcome.report.dump(2) << "\n";
  } else {
    std::cout << FormatFitSummary(outcome.report);
  }
  return 0;
}

const CommandRegistration kFitCommand(
    {"fit", "fit a prior, D-BRDF or analytic model to a session (or choose: auto)", RunFit});

}  // namespace
}  // namespace zbrdf::cli
