#include "tools/brdf_export.h"

#include <chrono>
#include <filesystem>

#include "acquisition/session_brdf.h"
#include "basis/atomic_file.h"
#include "basis/error.h"
#include "basis/option_checker.h"
#include "brdf/brdf_explorer.h"
#include "brdf/dbrdf.h"
#include "brdf/dbrdf_file.h"
#include "brdf/merl_export.h"
#include "brdf/merl_table.h"
#include "brdf/sh_brdf.h"
#include "brdf/sh_file.h"

namespace zbrdf {
namespace {

namespace fs = std::filesystem;

nlohmann::json CheckJson(const ValueCheck& check) {
  return {{"values", check.values},
          {"nan", check.nan},
          {"negative", check.negative},
          {"clamped", check.clamp && (check.nan > 0 || check.negative > 0)}};
}

// The SH data behind an input: its own (an SH file) or its session's (SessionShFiles), or none.
std::string ShSourceOf(const BrdfInput& input) {
  if (input.kind == "sh-file") return input.source;
  if (!input.session_dir.empty()) {
    const std::vector<std::string> files = SessionShFiles(input.session_dir);
    if (!files.empty()) return files.front();
  }
  return "";
}

std::string SpectralPath(const std::string& out) {
  const fs::path p(out);
  if (p.extension() == ".bsdf")
    return (p.parent_path() / (p.stem().string() + ".spectral.bsdf")).string();
  return out + ".spectral.bsdf";
}

void RequireOutFolder(const std::string& out) {
  const fs::path parent = fs::path(out).parent_path();
  if (!parent.empty() && !fs::is_directory(parent)) {
    throw InputError("--out " + out + ": the folder " + parent.string() +
                     " does not exist; create it first");
  }
}

}  // namespace

ExportFormat ParseExportFormat(const std::string& name) {
  if (name == "merl") return ExportFormat::kMerl;
  if (name == "rgl") return ExportFormat::kRgl;
  if (name == "sh") return ExportFormat::kSh;
  if (name == "dbrdf") return ExportFormat::kDBrdf;
  if (name == "brdf-explorer") return ExportFormat::kBrdfExplorer;
  throw InputError("--format must be one of merl, rgl, sh, dbrdf, brdf-explorer (got '" + name +
                   "')");
}

std::string ExportFormatName(ExportFormat format) {
  switch (format) {
    case ExportFormat::kMerl:
      return "merl";
    case ExportFormat::kRgl:
      return "rgl";
    case ExportFormat::kSh:
      return "sh";
    case ExportFormat::kDBrdf:
      return "dbrdf";
    case ExportFormat::kBrdfExplorer:
      return "brdf-explorer";
  }
  return "";
}

std::string MitsubaSceneSnippet(const std::string& bsdf_file, const std::string& what) {
  return "<!-- " + what +
         "\n     Mitsuba 3 scene: the material on a sphere under uniform light. The measured\n"
         "     plugin reads the rgb .bsdf in RGB variants (scalar_rgb, llvm_ad_rgb, ...).\n"
         "     Render: mitsuba -m scalar_rgb THIS_FILE -->\n"
         "<scene version=\"3.0.0\">\n"
         "    <bsdf type=\"measured\" id=\"zbrdf_material\">\n"
         "        <string name=\"filename\" value=\"" +
         bsdf_file +
         "\"/>\n"
         "    </bsdf>\n"
         "    <integrator type=\"path\"/>\n"
         "    <sensor type=\"perspective\">\n"
         "        <float name=\"fov\" value=\"32\"/>\n"
         "        <transform name=\"to_world\">\n"
         "            <lookat origin=\"0, 0, 4\" target=\"0, 0, 0\" up=\"0, 1, 0\"/>\n"
         "        </transform>\n"
         "        <sampler type=\"independent\">\n"
         "            <integer name=\"sample_count\" value=\"256\"/>\n"
         "        </sampler>\n"
         "        <film type=\"hdrfilm\">\n"
         "            <integer name=\"width\" value=\"512\"/>\n"
         "            <integer name=\"height\" value=\"512\"/>\n"
         "        </film>\n"
         "    </sensor>\n"
         "    <shape type=\"sphere\">\n"
         "        <ref id=\"zbrdf_material\"/>\n"
         "    </shape>\n"
         "    <emitter type=\"constant\">\n"
         "        <rgb name=\"radiance\" value=\"1.0\"/>\n"
         "    </emitter>\n"
         "</scene>\n";
}

std::string PbrtSceneSnippet(const std::string& bsdf_file, const std::string& what) {
  return "# " + what +
         "\n# pbrt-v4 scene: the material on a sphere under uniform light. pbrt-v4's measured\n"
         "# material reads the spectral .bsdf. Render: pbrt THIS_FILE\n"
         "LookAt 0 0 4  0 0 0  0 1 0\n"
         "Camera \"perspective\" \"float fov\" [ 32 ]\n"
         "Film \"rgb\" \"string filename\" [ \"zbrdf-ball.exr\" ]\n"
         "    \"integer xresolution\" [ 512 ] \"integer yresolution\" [ 512 ]\n"
         "Sampler \"zsobol\" \"integer pixelsamples\" [ 256 ]\n"
         "Integrator \"volpath\"\n"
         "WorldBegin\n"
         "LightSource \"infinite\" \"rgb L\" [ 1 1 1 ]\n"
         "AttributeBegin\n"
         "  Material \"measured\" \"string filename\" [ \"" +
         bsdf_file +
         "\" ]\n"
         "  Shape \"sphere\" \"float radius\" [ 1 ]\n"
         "AttributeEnd\n";
}

void ExportOptions::Validate() const {
  OptionChecker check("ExportOptions");
  check.Require(!out.empty(), "out", "must name the file to write (--out)");
  const bool rgb = rgl_variant != RglVariant::kSpectral;
  const bool spectral = rgl_variant != RglVariant::kRgb;
  for (const std::string& scene : scenes) {
    check.Require(scene == "mitsuba" || scene == "pbrt", "scenes",
                  "must be mitsuba, pbrt, both or none (--scene; got '" + scene + "')");
    if (format != ExportFormat::kRgl) continue;
    check.Require(scene != "mitsuba" || rgb, "scenes",
                  "mitsuba needs the rgb variant (Mitsuba's RGB variants read it): use "
                  "--rgl-variant rgb or both");
    check.Require(scene != "pbrt" || spectral, "scenes",
                  "pbrt needs the spectral variant (pbrt-v4 reads only it): use --rgl-variant "
                  "spectral or both");
  }
  check.Nested("rgl", rgl).ThrowIfInvalid();
}

ExportResult ExportBrdf(const BrdfInput& input, const ExportOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  options.Validate();
  RequireOutFolder(options.out);
  const Brdf& brdf = *input.brdf;
  ExportResult result;
  nlohmann::json& report = result.report;
  report["format"] = ExportFormatName(options.format);
  report["input"] = input.description;
  report["brdf"] = brdf.Spec();
  const std::string what = "zbrdf export of " + brdf.Spec().substr(0, 160);
  switch (options.format) {
    case ExportFormat::kMerl: {
      if (brdf.IsDelta()) {
        throw InputError("merl export: " + brdf.Spec() +
                         " is a delta (mirror) material; a table of "
                         "f_r values cannot hold it");
      }
      ValueCheck check;
      check.clamp = options.clamp_invalid;
      const MerlTable table = SampleMerlTable(brdf, &check);
      check.Finish("merl export of " + brdf.Spec());
      const std::string tmp = options.out + ".tmp.binary";
      WriteMerlBinary(tmp, table);
      fs::rename(tmp, options.out);
      result.files.push_back(options.out);
      report["values"] = CheckJson(check);
      report["sampling"] = "f_r at the centre of each of the 90 x 90 x 180 bins";
      break;
    }
    case ExportFormat::kRgl: {
      RglExportOptions rgl = options.rgl;
      rgl.clamp_invalid = options.clamp_invalid;
      if (rgl.description.empty()) rgl.description = what;
      // Tabulate once, build both variants, then write: a failure writes nothing.
      const bool want_rgb = options.rgl_variant != ExportOptions::RglVariant::kSpectral;
      const bool want_spectral = options.rgl_variant != ExportOptions::RglVariant::kRgb;
      const std::string rgb_file = want_rgb ? options.out : "";
      const std::string spectral_file = !want_spectral ? ""
                                        : want_rgb     ? SpectralPath(options.out)
                                                       : options.out;
      const fs::path base =
          fs::path(options.out).parent_path() / fs::path(options.out).stem().string();
      std::vector<std::pair<std::string, std::string>> scenes;  // path, text
      // ExportOptions::Validate() checked the scene names against the variants.
      for (const std::string& scene : options.scenes) {
        if (scene == "mitsuba") {
          scenes.emplace_back(base.string() + ".mitsuba.xml",
                              MitsubaSceneSnippet(fs::path(rgb_file).filename().string(), what));
        } else {
          scenes.emplace_back(base.string() + ".pbrt",
                              PbrtSceneSnippet(fs::path(spectral_file).filename().string(), what));
        }
      }
      RglExportReport r;
      TensorFile rgb_tensors, spectral_tensors;
      MakeRglTensors(brdf, rgl, &r, want_rgb ? &rgb_tensors : nullptr,
                     want_spectral ? &spectral_tensors : nullptr);
      if (want_rgb) {
        WriteTensorFile(rgb_file, rgb_tensors);
        result.files.push_back(rgb_file);
      }
      if (want_spectral) {
        WriteTensorFile(spectral_file, spectral_tensors);
        result.files.push_back(spectral_file);
        report["spectral"] = {{"out_of_gamut_nodes", r.out_of_gamut},
                              {"max_relative_gamut_error", r.max_gamut_error},
                              {"wavelengths_nm", "380..780 step 10"}};
      }
      for (const auto& [path, text] : scenes) {
        WriteFileAtomically(path, text);
        result.files.push_back(path);
      }
      report["values"] = CheckJson(r.values);
      report["isotropic"] = r.isotropic;
      report["ndf"] = r.ndf_source;
      report["resolution"] = {
          {"theta_nodes", rgl.theta_nodes},
          {"phi_nodes", r.isotropic ? 1 : rgl.phi_nodes},
          {"ndf", rgl.ndf_resolution},
          {"vndf", r.isotropic ? rgl.vndf_resolution : rgl.vndf_resolution_anisotropic},
          {"samples", rgl.sample_resolution}};
      break;
    }
    case ExportFormat::kSh: {
      const std::string source = ShSourceOf(input);
      if (source.empty()) {
        throw InputError(
            "sh export needs SH data: a session converted with zbrdf convert, or its "
            "sh-<target>.exr. " +
            input.description + " has none (formats for any BRDF: merl, rgl, brdf-explorer)");
      }
      const ShBrdfData data = ReadShFile(source);
      WriteShFile(options.out, data);
      result.files.push_back(options.out);
      report["source"] = source;
      report["target"] = TargetName(data.target);
      report["order"] = data.order;
      break;
    }
    case ExportFormat::kDBrdf: {
      const auto* dbrdf = dynamic_cast<const DBrdf*>(&brdf);
      if (!dbrdf) {
        throw InputError(
            "dbrdf export needs a D-BRDF: a session fitted with zbrdf fit, its "
            "fit-dbrdf.exr, or a dbrdf: spec. " +
            input.description + " is not one (formats for any BRDF: merl, rgl, brdf-explorer)");
      }
      nlohmann::json info = {{"exported_by", "zbrdf export"}, {"input", input.description}};
      if (input.kind == "dbrdf-file" || input.kind == "session") {
        if (fs::path(input.source).extension() == ".exr")
          info["fit"] = ReadDBrdfFileInfo(input.source);
      }
      WriteDBrdfFile(options.out, *dbrdf, info);
      result.files.push_back(options.out);
      report["theta_samples"] = dbrdf->table().theta_samples;
      report["phi_samples"] = dbrdf->table().phi_samples;
      break;
    }
    case ExportFormat::kBrdfExplorer: {
      WriteBrdfExplorerFile(options.out, brdf);
      result.files.push_back(options.out);
      break;
    }
  }
  report["files"] = result.files;
  report["seconds"] =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace zbrdf
