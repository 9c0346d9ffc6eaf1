// zbrdf.fit and zbrdf.export: the code `zbrdf fit` and `zbrdf export` run (tools/fit_session.h,
// tools/brdf_export.h), with the same options and defaults, returning their reports as dicts.
#include <string>
#include <utility>
#include <vector>

#include <pybind11/stl.h>

#include "basis/error.h"
#include "python/bindings.h"
#include "tools/brdf_export.h"
#include "tools/brdf_input.h"
#include "tools/fit_session.h"

namespace zbrdf::python {
namespace {

py::object Fit(const py::handle& session_value, const std::string& model, const py::handle& prior,
               const std::vector<std::string>& exclude, const std::vector<std::string>& candidates,
               int replicates, double model_error, const std::string& table,
               std::pair<double, double> f0_range, const py::handle& figure, bool write,
               bool compare, FitContext* context, bool return_model) {
  const std::string session_dir = PathArgument(session_value, "session_dir");
  // The flags of `zbrdf fit` (tools/cli/fit.cc), field by field.
  FitSessionOptions options;
  options.model = model;
  if (table == "1d") {
    options.dbrdf.table = DBrdfFitOptions::Table::kIsotropic;
  } else if (table == "2d") {
    options.dbrdf.table = DBrdfFitOptions::Table::kAnisotropic;
  } else if (table != "auto") {
    throw InputError("table must be auto, 1d or 2d (got " + table + ")");
  }
  options.dbrdf.f0_min = f0_range.first;
  options.dbrdf.f0_max = f0_range.second;
  if (!prior.is_none()) options.prior_path = PathArgument(prior, "prior");
  options.prior.exclude = exclude;
  options.auto_candidates = candidates;
  options.prior.replicates = replicates;
  options.prior.model_error_floor = model_error;
  options.write_outputs = write;
  options.compare = compare;
  if (!figure.is_none()) options.figure_path = PathArgument(figure, "figure");
  FitSessionOutcome outcome;
  {
    py::gil_scoped_release release;
    outcome = FitSession(session_dir, options, context);
  }
  py::object report = ToPython(outcome.report);
  if (!return_model) return report;
  BrdfInput fitted;
  fitted.brdf = outcome.model;
  fitted.kind = "fit";
  fitted.source = session_dir;
  fitted.session_dir = session_dir;
  fitted.name = outcome.report.value("model", model);
  fitted.description = "the " + fitted.name + " fit of session " + session_dir;
  return py::make_tuple(report, py::cast(std::move(fitted)));
}

py::object Export(const py::handle& source, const std::string& format, const py::handle& out,
                  bool clamp_invalid, const std::string& rgl_variant, const py::handle& scenes,
                  int rgl_theta, int rgl_phi, int rgl_samples) {
  // The source: a zbrdf.Brdf as loaded, or anything zbrdf.load accepts.
  BrdfInput input;
  const bool loaded = py::isinstance<BrdfInput>(source);
  if (loaded) input = source.cast<BrdfInput>();
  const std::string source_text = loaded ? "" : PathArgument(source, "source");
  // The flags of `zbrdf export` (tools/cli/export.cc), field by field.
  ExportOptions options;
  options.format = ParseExportFormat(format);
  options.out = PathArgument(out, "out_path");
  options.clamp_invalid = clamp_invalid;
  if (rgl_variant == "rgb") {
    options.rgl_variant = ExportOptions::RglVariant::kRgb;
  } else if (rgl_variant == "spectral") {
    options.rgl_variant = ExportOptions::RglVariant::kSpectral;
  } else if (rgl_variant != "both") {
    throw InputError("rgl_variant must be rgb, spectral or both (got '" + rgl_variant + "')");
  }
  if (!scenes.is_none()) {
    options.scenes = scenes.cast<std::vector<std::string>>();
    if (options.format != ExportFormat::kRgl && !options.scenes.empty()) {
      throw InputError(
          "scenes: scene snippets go with format rgl (Mitsuba 3 and pbrt-v4 read measured "
          "materials from .bsdf files)");
    }
  } else if (options.format != ExportFormat::kRgl) {
    options.scenes.clear();
  } else if (options.rgl_variant == ExportOptions::RglVariant::kRgb) {
    options.scenes = {"mitsuba"};
  } else if (options.rgl_variant == ExportOptions::RglVariant::kSpectral) {
    options.scenes = {"pbrt"};
  }
  options.rgl.theta_nodes = rgl_theta;
  options.rgl.phi_nodes = rgl_phi;
  options.rgl.sample_resolution = rgl_samples;
  ExportResult result;
  {
    py::gil_scoped_release release;
    if (!loaded) input = ResolveBrdfInput(source_text);
    result = ExportBrdf(input, options);
  }
  return ToPython(result.report);
}

}  // namespace

void BindPipeline(py::module_& m) {
  py::class_<FitContext>(m, "FitContext",
                         "Fitters kept between zbrdf.fit calls on sessions of the same zone and "
                         "order (their precomputation is most of a fit's time), and priors read "
                         "once. Pass one as context= to fit many sessions.")
      .def(py::init<>());
  const FitSessionOptions defaults;
  m.def("fit", &Fit, py::arg("session_dir"), py::arg("model") = "auto", py::kw_only(),
        py::arg("prior") = py::none(), py::arg("exclude") = std::vector<std::string>{},
        py::arg("candidates") = defaults.auto_candidates,
        py::arg("replicates") = defaults.prior.replicates,
        py::arg("model_error") = defaults.prior.model_error_floor, py::arg("table") = "auto",
        py::arg("f0_range") = std::make_pair(defaults.dbrdf.f0_min, defaults.dbrdf.f0_max),
        py::arg("figure") = py::none(), py::arg("write") = true, py::arg("compare") = true,
        py::arg("context") = static_cast<FitContext*>(nullptr), py::arg("return_model") = false,
        "Fits a model to a session's zonal.exr as `zbrdf fit` does (docs/fitting.md, "
        "docs/prior.md) and returns its report as a dict (the JSON of `zbrdf fit --json`). "
        "model: auto (cross-validated choice among candidates), prior, dbrdf, ggx, ward or as. "
        "The keyword arguments are the flags of `zbrdf fit`: prior (--prior), exclude "
        "(--exclude), candidates, replicates, model_error (--model-error), table (auto, 1d, "
        "2d), f0_range (--f0-range), figure (PNG path), write=False (--no-write), compare=False "
        "(--no-compare). context: a zbrdf.FitContext reused across calls. return_model=True "
        "returns (report, zbrdf.Brdf of the fitted model). Runs without the GIL.");
  m.def("export", &Export, py::arg("source"), py::arg("format"), py::arg("out_path"), py::kw_only(),
        py::arg("clamp_invalid") = false, py::arg("rgl_variant") = "both",
        py::arg("scenes") = py::none(), py::arg("rgl_theta") = 16, py::arg("rgl_phi") = 25,
        py::arg("rgl_samples") = 48,
        "Writes a BRDF as `zbrdf export` does (docs/formats.md) and returns its report as a "
        "dict (`zbrdf export --json`; 'files' lists what was written). source: a zbrdf.Brdf or "
        "anything zbrdf.load accepts. format: merl, rgl, sh, dbrdf or brdf-explorer. The "
        "keyword arguments are its flags: clamp_invalid, rgl_variant (rgb, spectral, both), "
        "scenes (list of mitsuba, pbrt; default as the CLI: those the variants allow), "
        "rgl_theta, rgl_phi, rgl_samples. Runs without the GIL.");
}

}  // namespace zbrdf::python
