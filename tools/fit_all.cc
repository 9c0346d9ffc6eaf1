#include "tools/fit_all.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>
#include <set>

#include "acquisition/session.h"
#include "basis/atomic_file.h"
#include "basis/error.h"
#include "basis/option_checker.h"
#include "basis/parallel.h"
#include "brdf/nbrdf.h"
#include "rig/rig.h"
#include "tools/fit_session.h"
#include "tools/json_file.h"
#include "tools/virtual_capture.h"

namespace zbrdf {
namespace {

bool StartsSpec(const std::string& token) {
  const size_t colon = token.find(':'), equals = token.find('=');
  return colon != std::string::npos && (equals == std::string::npos || colon < equals);
}

double MedianOf(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The camera's longest exposure from a "ExposureTime X us is outside [MIN, MAX] us" message, or
// 0 if the message is not about the exposure range.
double LongestExposureUs(const std::string& message) {
  if (message.find("ExposureTime") == std::string::npos) return 0;
  const size_t open = message.find('[', message.find("outside"));
  const size_t comma = message.find(',', open);
  if (open == std::string::npos || comma == std::string::npos) return 0;
  return std::atof(message.c_str() + comma + 1);
}

}  // namespace

std::vector<std::string> ExpandMaterialList(const std::string& list) {
  std::vector<std::string> specs;
  size_t start = 0;
  while (start <= list.size()) {
    size_t end = list.find(',', start);
    if (end == std::string::npos) end = list.size();
    std::string token = list.substr(start, end - start);
    token.erase(0, token.find_first_not_of(" \t"));
    token.erase(token.find_last_not_of(" \t") + 1);
    if (!token.empty()) {
      if (StartsSpec(token) || specs.empty()) {
        specs.push_back(token);
      } else {
        specs.back() += "," + token;
      }
    }
    start = end + 1;
  }
  std::vector<std::string> out;
  for (const std::string& spec : specs) {
    if (spec == "merl:*" || spec == "rgl:*") {
      const std::string set = spec.substr(0, spec.find(':'));
      for (const std::string& name : BundledMaterialNames(set)) out.push_back(set + ":" + name);
    } else {
      out.push_back(spec);
    }
  }
  return out;
}

std::string MaterialFolderName(const std::string& spec) {
  std::string name;
  for (char c : spec) {
    const bool keep = std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-';
    name += keep ? c : '-';
  }
  while (name.find("--") != std::string::npos) name.erase(name.find("--"), 1);
  if (name.size() > 100) name.resize(100);
  return name.empty() ? "material" : name;
}

void AddMaterialItems(const std::vector<std::string>& specs, const std::string& id_prefix,
                      const std::string& result_folder, BatchManifest* manifest) {
  std::set<std::string> folders;
  for (const std::string& spec : specs) {
    const std::string folder = MaterialFolderName(spec);
    if (!folders.insert(folder).second) {
      throw InputError("--materials names '" + spec + "' twice (or two specs that share the folder " +
                       folder + "); list each material once");
    }
    manifest->items.push_back({id_prefix + folder, "items/" + result_folder + folder + ".json"});
  }
}

void FitAllOptions::Validate() const {
  OptionChecker check("FitAllOptions");
  check.Require(!materials.empty(), "materials", "must not be empty (--materials)")
      .Require(!out_dir.empty(), "out_dir", "must name the output folder (--out)")
      .Require(preset == "fast" || preset == "full", "preset",
               "must be fast or full (got '" + preset + "')")
      .InRange("order", order, 0, 30);
  for (const std::string& m : models) {
    check.Require(m == "dbrdf" || m == "ggx" || m == "ward" || m == "as", "models",
                  "must each be dbrdf, ggx, ward or as (got '" + m + "' in --models)");
  }
  check.InRange("parallel_materials", parallel_materials, 1, 16).ThrowIfInvalid();
}

namespace {

// The table from rows (in order): fit-all.json's object.
nlohmann::json FitAllTable(const nlohmann::json& batch_options, const std::vector<nlohmann::json>& rows) {
  std::vector<std::string> models;
  for (const auto& m : batch_options["models"]) models.push_back(m.get<std::string>());
  nlohmann::json all_rows = nlohmann::json::array();
  std::map<std::string, std::vector<double>> errors, errors_80, errors_zone;
  std::map<std::string, std::pair<double, std::string>> worst;
  for (nlohmann::json row : rows) {
    row.erase("batch_options");
    for (const std::string& m : models) {
      const nlohmann::json& e80 = row["error_cosine_l2_80"][m];
      if (e80.is_number()) errors_80[m].push_back(e80.get<double>());
      const nlohmann::json& ez = row["error_in_zone"][m];
      if (ez.is_number()) errors_zone[m].push_back(ez.get<double>());
      const nlohmann::json& e = row["error_cosine_l2"][m];
      if (e.is_number()) {
        errors[m].push_back(e.get<double>());
        if (e.get<double>() > worst[m].first || worst[m].second.empty()) {
          worst[m] = {e.get<double>(), row["material"].get<std::string>()};
        }
      }
    }
    all_rows.push_back(std::move(row));
  }
  auto median_or_null = [](const std::vector<double>& v) {
    return v.empty() ? nlohmann::json(nullptr) : nlohmann::json(MedianOf(v));
  };
  nlohmann::json stats = nlohmann::json::object();
  for (const std::string& m : models) {
    const auto& v = errors[m];
    stats[m] = {{"materials", v.size()},
                {"median_error_cosine_l2", median_or_null(v)},
                {"worst_error_cosine_l2", v.empty() ? nlohmann::json(nullptr) : nlohmann::json(worst[m].first)},
                {"worst_material", worst[m].second},
                {"median_error_cosine_l2_80", median_or_null(errors_80[m])},
                {"median_error_in_zone", median_or_null(errors_zone[m])}};
  }
  return {{"rig", batch_options["rig"]},   {"preset", batch_options["preset"]},
          {"order", batch_options["order"]}, {"seed", batch_options["seed"]},
          {"models", models},               {"rows", all_rows},
          {"summary", stats}};
}

void WriteFitAllTable(const std::string& out_dir, const nlohmann::json& table) {
  WriteFileAtomically(out_dir + "/fit-all.json", table.dump(2) + "\n");
  std::vector<std::string> models = table["models"].get<std::vector<std::string>>();
  std::string csv = "material,folder";
  for (const std::string& m : models) {
    csv += ',' + m + "_error_cosine_l2," + m + "_error_in_zone," + m + "_error_cosine_l2_80";
  }
  csv += "\n";
  for (const auto& row : table["rows"]) {
    // Specs contain commas: quote the field (RFC 4180).
    csv += '"' + row["material"].get<std::string>() + "\"," + row["folder"].get<std::string>();
    for (const std::string& m : models) {
      for (const char* key : {"error_cosine_l2", "error_in_zone", "error_cosine_l2_80"}) {
        const nlohmann::json& e = row[key][m];
        char value[32] = "";
        if (e.is_number()) std::snprintf(value, sizeof(value), "%.6g", e.get<double>());
        csv += std::string(",") + value;
      }
    }
    csv += "\n";
  }
  WriteFileAtomically(out_dir + "/fit-all.csv", csv);
}

}  // namespace

BatchManifest FitAllManifest(const FitAllOptions& options) {
  options.Validate();
  const Rig rig = ApplyPreset(LoadRig(options.rig_path), ParsePreset(options.preset));
  BatchManifest manifest;
  manifest.command = "fit-all";
  manifest.args = options.command_args;
  manifest.options = {{"rig", rig.name},   {"rig_hash", RigHashHex(rig)},          {"preset", options.preset},
                      {"order", options.order}, {"seed", options.seed}, {"models", options.models}};
  AddMaterialItems(options.materials, "", "", &manifest);
  return manifest;
}

FitAllSummary ReduceFitAll(const std::string& out_dir) {
  const BatchManifest manifest = ReadManifest(out_dir, "fit-all");
  std::vector<nlohmann::json> rows;
  FitAllSummary summary;
  for (const BatchItem& item : manifest.items) {
    nlohmann::json row = ReadItemResult(out_dir, manifest, item);
    if (row.is_null()) continue;
    summary.failed += row.contains("failure");
    rows.push_back(std::move(row));
  }
  summary.items = static_cast<int>(manifest.items.size());
  summary.table = FitAllTable(manifest.options, rows);
  WriteFitAllTable(out_dir, summary.table);
  return summary;
}

FitAllSummary RunFitAll(const FitAllOptions& options) {
  options.Validate();
  const Rig rig = ApplyPreset(LoadRig(options.rig_path), ParsePreset(options.preset));
  const BatchManifest manifest = FitAllManifest(options);
  PrepareManifest(options.out_dir, manifest, options.shard);
  FitContext context;
  const std::vector<size_t> owned = options.shard.ItemsOf(manifest.items.size());
  const int total = static_cast<int>(owned.size());
  std::mutex mutex;
  FitAllSummary summary;
  summary.items = total;
  std::atomic<int> finished{0};
  std::exception_ptr table_error;
  Report(options.progress, {"fit-all", 0, total, "materials"});
  // A whole run keeps the table current after every material; a shard leaves it to the merge.
  auto write_table = [&]() {  // under mutex
    if (!options.shard.IsWhole()) return;
    const FitAllSummary reduced = ReduceFitAll(options.out_dir);
    summary.table = reduced.table;
  };

  // One material: simulate (or reuse) its session, then fit each model; false stops this worker
  // (interrupted, or the table could not be written).
  auto fit_material = [&](int i) {
    if (options.interrupt && options.interrupt->load()) return false;
    const std::string& spec = options.materials[i];
    const BatchItem& item = manifest.items[i];
    if (!options.refit && ReadItemResult(options.out_dir, manifest, item).is_object()) {
      std::lock_guard<std::mutex> lock(mutex);
      ++summary.reused_items;
      Report(options.progress, {"fit-all", ++finished, total, "materials"});
      return true;
    }
    const RunningMarker running(options.out_dir, item);
    const std::string folder = item.id;
    const std::string dir = options.out_dir + "/" + folder;
    nlohmann::json row = {{"material", spec}, {"folder", folder}};
    row["error_cosine_l2"] = nlohmann::json::object();
    row["error_in_zone"] = nlohmann::json::object();
    row["error_cosine_l2_80"] = nlohmann::json::object();
    row["fit_time_s"] = nlohmann::json::object();
    row["conditions"] = nlohmann::json::object();
    bool simulated = false, reused_session = false, failed = false;
    int fitted = 0, reused_fits = 0;
    try {
      if (!std::filesystem::exists(SessionPath(dir, kZonalFile))) {
        VirtualCaptureArgs args;
        args.rig = rig;
        args.preset_name = options.preset;
        args.material_spec = spec;
        args.seed = options.seed;
        args.job.out_dir = dir;
        args.job.order = options.order;
        args.job.resume = SessionFolder::Exists(dir);
        args.job.interrupt = options.interrupt;
        VirtualCaptureOutcome outcome;
        try {
          outcome = RunVirtualCapture(args);
        } catch (const DeviceError& e) {
          // A very dark material: the metered exposure exceeds the camera's range. Capture with
          // the longest bracket the camera allows instead (noisier, but data), keeping the
          // failed attempt's folder aside.
          const std::string message = e.what();
          const double longest = LongestExposureUs(message);
          if (longest <= 0) throw;
          std::filesystem::rename(dir, dir + ".exposure-failed");
          args.job.resume = false;
          args.job.shortest_exposure_us =
              longest / std::pow(2.0, args.job.stops_apart * (args.job.exposures - 1));
          outcome = RunVirtualCapture(args);
          row["capture_note"] = "metered exposure beyond the camera's range (" + message +
                                "); captured with the longest exposures it allows";
        }
        if (!outcome.result.complete) return false;  // interrupted: resumable
        simulated = true;
      } else {
        reused_session = true;
      }
      for (const std::string& model : options.models) {
        const std::string report_path = SessionPath(dir, FitReportFileName(model));
        nlohmann::json report = options.refit ? nlohmann::json(nullptr) : ReadJsonOrNull(report_path);
        if (report.is_null() || !report.contains("error_cosine_l2")) {
          FitSessionOptions fit;
          fit.model = model;
          report = FitSession(dir, fit, &context).report;
          ++fitted;
        } else {
          ++reused_fits;
        }
        row["error_cosine_l2"][model] = report.value("error_cosine_l2", nlohmann::json(nullptr));
        row["error_in_zone"][model] = report.value("error_in_zone", nlohmann::json(nullptr));
        row["error_cosine_l2_80"][model] =
            report.value("error_cosine_l2_80", nlohmann::json(nullptr));
        row["fit_time_s"][model] = report.value("fit_time_s", nlohmann::json(nullptr));
        row["conditions"][model] = report.value("conditions", nlohmann::json::array());
      }
    } catch (const std::exception& e) {
      row["failure"] = e.what();
      failed = true;
    }
    std::lock_guard<std::mutex> lock(mutex);
    try {
      WriteItemResult(options.out_dir, manifest, item, row);
    } catch (...) {
      if (!table_error) table_error = std::current_exception();
      return false;
    }
    summary.simulated += simulated;
    summary.reused_sessions += reused_session;
    summary.fitted += fitted;
    summary.reused_fits += reused_fits;
    summary.failed += failed;
    try {
      write_table();
    } catch (...) {
      if (!table_error) table_error = std::current_exception();
      return false;
    }
    Report(options.progress, {"fit-all", ++finished, total, "materials"});
    return true;
  };
  // Materials in flight at once: each stage is itself mostly single-threaded.
  ParallelForEach(total, std::clamp(options.parallel_materials, 1, 16),
                  [&](int64_t i) { return fit_material(static_cast<int>(owned[i])); });
  if (table_error) std::rethrow_exception(table_error);
  summary.interrupted = finished.load() < total;
  write_table();
  return summary;
}

}  // namespace zbrdf
