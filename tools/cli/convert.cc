// zbrdf convert: a session's zonal coefficients to spherical harmonics (SH file for renderers).
#include <cmath>
#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "acquisition/session.h"
#include "acquisition/zonal.h"
#include "basis/error.h"
#include "brdf/sh_brdf.h"
#include "fitting/fit_error.h"
#include "tools/cli/command.h"
#include "tools/fit_session.h"
#include "tools/sh_conversion.h"

namespace zbrdf::cli {
namespace {

nlohmann::json Finite(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

int RunConvert(const std::vector<std::string>& args) {
  CommandLine cl("convert",
                 "Converts a session's zonal coefficients (zonal.exr) to a tensor-product SH\n"
                 "expansion in w_i and w_r by the moment form (docs/design.md section 3),\n"
                 "regularized from the data's variances, and writes an SH file with per-exitant\n"
                 "tables on a 90 x 90 (theta_r, phi_r) grid (docs/sh-and-dbrdf-files.md).");
  cl.Positional("SESSION", "session folder holding zonal.exr")
      .Option("to", "FORMAT", "output representation (sh)", "sh")
      .Option("sh-order", "L", "target order (default: the data's zonal order)")
      .Option("target", "T", "sh, sh-even, sh-odd or hsh", "sh")
      .Option("tau", "T", "singular-value truncation threshold (default: chosen from the data's "
                          "variances)")
      .Option("out", "FILE", "output file (default SESSION/sh-<target>.exr)")
      .Flag("no-compare", "skip the comparison with a simulated session's true material")
      .Flag("json", "print the report as one JSON object")
      .Epilog("Example:\n"
              "  zbrdf convert results/blue-acrylic --to sh --target sh --json\n\n"
              "JSON keys: session, output, target, sh_order, tau, tau_rule, noise_gain,\n"
              "truncated_components, underdetermined_components, kept_directions,\n"
              "shannon_number, exitant_grid, warnings, and for simulated\n"
              "sessions material, error_in_zone, error_outside_zone, error_cosine_l2 (relative L2\n"
              "of f_r cos(theta_i), unclamped) and negative_fraction (share of the hemisphere\n"
              "pairs where the SH function is negative).");
  if (!cl.Parse(args)) return 0;
  if (cl.Get("to") != "sh") throw InputError("--to supports sh (got " + cl.Get("to") + ")");
  const std::string session = cl.Positional(0);
  const ZonalData zonal = ReadZonalExr(SessionPath(session, kZonalFile));
  const ZonalTensor data = ToZonalTensor(zonal);
  ShConversionOptions options;
  options.target = ParseTargetName(cl.Get("target"));
  if (cl.Has("sh-order")) options.order = cl.GetInt("sh-order", 0, 30);
  if (cl.Has("tau")) options.tau = cl.GetDouble("tau", 0.0, 0.999);
  const ShConversionResult result = ConvertToSh(data, options);
  const std::string out = cl.Has("out") ? cl.Get("out")
                                        : SessionPath(session, ShFileName(TargetName(options.target)));
  WriteShFile(out, result.data);
  nlohmann::json report = result.ToJson();
  report["session"] = session;
  report["output"] = out;
  report["order"] = data.order;
  if (!cl.Has("no-compare")) {
    if (const auto truth = SessionMaterial(session)) {
      const ShBrdf sh(result.data);
      const CosineWeightedFn f = [&sh](const Vec3& w_o, std::span<const Vec3> w_i, std::span<Rgb> o) {
        sh.CosineWeightedBatch(w_o, w_i, o);
      };
      const BrdfComparison c = CompareBrdfs(f, CosineWeightedOf(*truth), data.zone());
      report["material"] = truth->Spec();
      report["error_in_zone"] = Finite(c.in_zone);
      report["error_outside_zone"] = c.has_outside ? Finite(c.outside_zone) : nlohmann::json(nullptr);
      report["error_cosine_l2"] = Finite(c.cosine_l2);
      report["negative_fraction"] = c.negative_fraction;
    }
  }
  if (cl.Has("json")) {
    std::cout << report.dump(2) << "\n";
    return 0;
  }
  std::printf("converted %s (order %d, zone %.1f-%.1f deg) to %s order %d -> %s\n", session.c_str(),
              data.order, RadToDeg(data.theta_min_rad), RadToDeg(data.theta_max_rad),
              TargetName(options.target).c_str(), result.data.order, out.c_str());
  std::printf("  tau %.3g (%s); noise gain %.3g; %d of %d singular directions kept, %d truncated\n",
              result.tau, result.tau_automatic ? "automatic" : "given", result.diagnostics.noise_gain,
              result.kept_directions, result.singular_directions,
              result.diagnostics.truncated_components);
  if (report.contains("material")) {
    // An error is null where it is undefined (a delta material's f_r is a distribution).
    const auto percent = [&report](const char* key) {
      const nlohmann::json& v = report[key];
      if (!v.is_number()) return std::string("n/a");
      char text[32];
      std::snprintf(text, sizeof(text), "%.2f%%", 100 * v.get<double>());
      return std::string(text);
    };
    std::printf("  error vs %s (f_r cos theta_i, relative L2): %s in the zone",
                report["material"].get<std::string>().c_str(), percent("error_in_zone").c_str());
    if (!report["error_outside_zone"].is_null()) {
      std::printf(", %s outside", percent("error_outside_zone").c_str());
    }
    std::printf(", %s over the hemisphere; negative over %s of it\n",
                percent("error_cosine_l2").c_str(), percent("negative_fraction").c_str());
  }
  for (const std::string& w : result.warnings) std::printf("  warning: %s\n", w.c_str());
  return 0;
}

const CommandRegistration kConvertCommand({"convert",
                                           "convert a session's zonal data to spherical harmonics",
                                           RunConvert});

}  // namespace
}  // namespace zbrdf::cli
