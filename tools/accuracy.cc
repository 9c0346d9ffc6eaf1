#include "tools/accuracy.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>

#include "acquisition/session.h"
#include "basis/atomic_file.h"
#include "basis/data_path.h"
#include "basis/error.h"
#include "basis/option_checker.h"
#include "basis/parallel.h"
#include "brdf/brdf_prior.h"
#include "brdf/material_spec.h"
#include "pictures/accuracy_plots.h"
#include "pictures/environment.h"
#include "pictures/material_ball.h"
#include "rig/rig.h"
#include "tools/fit_all.h"
#include "tools/fit_session.h"
#include "tools/json_file.h"
#include "tools/virtual_capture.h"

namespace zbrdf {
namespace {

namespace fs = std::filesystem;

nlohmann::json Num(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

double Median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string RigPath(const std::string& rig) {
  if (rig.find('/') != std::string::npos || rig.find(".yaml") != std::string::npos) return rig;
  return DataPath("rig/rigs/" + rig + ".yaml");
}

std::string RigLabel(const std::string& rig) { return fs::path(rig).stem().string(); }

std::string ConfigLabel(const std::string& rig, int order) {
  return RigLabel(rig) + "-o" + std::to_string(order);
}

// Ngan et al. 2005's best dense fit per MERL material: {full, theta <= 80}.
std::map<std::string, std::pair<double, double>> NganBaseline() {
  std::map<std::string, std::pair<double, double>> out;
  std::ifstream in(DataPath("data/baselines/ngan2005-best-fits.csv"));
  std::string line;
  std::getline(in, line);  // header: material,best_model_full,best_rel_err_full,best_model_80,best_rel_err_80
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::stringstream ss(line);
    std::string item;
    while (std::getline(ss, item, ',')) f.push_back(item);
    if (f.size() >= 5) out[f[0]] = {std::atof(f[2].c_str()), std::atof(f[4].c_str())};
  }
  return out;
}

// The balls every image error is measured under: one environment and the render settings.
struct BallScene {
  const Environment* env = nullptr;
  BallOptions options;
  BallImage black;  // a black material's ball: the background alone, the error's norm
};

BallScene MakeBallScene(const Environment& env, int size, int spp, uint64_t seed) {
  BallScene scene;
  scene.env = &env;
  scene.options.size = size;
  scene.options.spp = spp;
  scene.options.seed = seed;
  scene.black = RenderBall(*MakeBrdf("lambert:0"), &env, scene.options);
  return scene;
}

// Relative RMSE of a model's ball against the truth's, under one scene.
double BallError(const Brdf& model, const Brdf& truth, const BallScene& scene) {
  const BallImage t = RenderBall(truth, scene.env, scene.options);
  const BallImage m = RenderBall(model, scene.env, scene.options);
  const double norm = BallRmse(t, scene.black);
  return norm > 0 ? BallRmse(t, m) / norm : NAN;
}

}  // namespace

std::string MaterialDevice(const std::string& spec) {
  if (spec.rfind("merl:", 0) == 0) return "merl";
  if (spec.rfind("rgl:", 0) == 0) return "rgl";
  return "other";
}

void AccuracyOptions::Validate() const {
  OptionChecker check("AccuracyOptions");
  check.Require(!out_dir.empty(), "out_dir", "must name the output folder (--out)")
      .Require(!rigs.empty(), "rigs", "must name at least one rig (--rigs)")
      .Require(!orders.empty(), "orders", "must name at least one order (--orders)")
      .Require(!materials.empty(), "materials", "must not be empty (--materials)")
      .Require(!candidates.empty(), "candidates", "must name at least one model (--candidates)")
      .Require(preset == "fast" || preset == "full", "preset",
               "must be fast or full (got '" + preset + "')")
      .InRange("ball_size", ball_size, 16, 1024)
      .InRange("ball_spp", ball_spp, 1, 4096)
      .InRange("parallel_items", parallel_items, 1, 16);
  for (int order : orders) check.InRange("orders", order, 1, 20);
  for (const std::string& c : candidates) {
    check.Require(c == "prior" || c == "dbrdf" || c == "ggx" || c == "ward" || c == "as",
                  "candidates", "must each be prior, dbrdf, ggx, ward or as (got '" + c + "')");
  }
  check.ThrowIfInvalid();
}

namespace {

struct AccuracyItem {
  std::string rig;
  int order;
  std::string material;
};

std::vector<std::string> AccuracyMaterials(const AccuracyOptions& options) {
  std::vector<std::string> materials;
  for (const std::string& m : options.materials) {
    for (const std::string& s : ExpandMaterialList(m)) materials.push_back(s);
  }
  return materials;
}

std::vector<AccuracyItem> AccuracyItems(const AccuracyOptions& options) {
  const std::vector<std::string> materials = AccuracyMaterials(options);
  std::vector<AccuracyItem> items;
  for (const std::string& rig : options.rigs) {
    for (int order : options.orders) {
      for (const std::string& m : materials) items.push_back({rig, order, m});
    }
  }
  return items;
}

}  // namespace

BatchManifest AccuracyManifest(const AccuracyOptions& options) {
  options.Validate();
  BatchManifest manifest;
  manifest.command = "accuracy";
  manifest.args = options.command_args;
  nlohmann::json rigs = nlohmann::json::array();
  for (const std::string& rig : options.rigs) {
    rigs.push_back({{"rig", RigLabel(rig)},
                    {"hash", RigHashHex(ApplyPreset(LoadRig(RigPath(rig)), ParsePreset(options.preset)))}});
  }
  manifest.options = {{"rigs", rigs},
                      {"orders", options.orders},
                      {"preset", options.preset},
                      {"candidates", options.candidates},
                      {"prior", options.prior_path.empty() ? DefaultPriorPath() : options.prior_path},
                      {"leave_one_out", options.leave_one_out},
                      {"images", options.images},
                      {"ball_size", options.ball_size},
                      {"ball_spp", options.ball_spp},
                      {"seed", options.seed}};
  // Items in AccuracyItems' order: rig, then order, then material.
  const std::vector<std::string> materials = AccuracyMaterials(options);
  for (const std::string& rig : options.rigs) {
    for (int order : options.orders) {
      const std::string label = ConfigLabel(rig, order);
      AddMaterialItems(materials, label + ".", label + "/", &manifest);
    }
  }
  return manifest;
}

AccuracySummary RunAccuracy(const AccuracyOptions& options) {
  options.Validate();
  const BatchManifest manifest = AccuracyManifest(options);
  const std::vector<AccuracyItem> all_items = AccuracyItems(options);
  const std::string prior_path = options.prior_path.empty() ? DefaultPriorPath() : options.prior_path;
  const BrdfPrior prior = ReadPriorFile(prior_path);
  const auto ngan = NganBaseline();
  PrepareManifest(options.out_dir, manifest, options.shard);
  const std::vector<size_t> owned = options.shard.ItemsOf(all_items.size());
  std::map<std::string, Rig> rigs;
  for (const std::string& rig : options.rigs) {
    rigs.emplace(rig, ApplyPreset(LoadRig(RigPath(rig)), ParsePreset(options.preset)));
  }
  fs::create_directories(options.out_dir);
  const Environment sky = Environment::Sky(), studio = Environment::Studio();
  // The black balls are the same for every item: rendered once.
  std::optional<BallScene> sky_scene, studio_scene;
  if (options.images) {
    sky_scene = MakeBallScene(sky, options.ball_size, options.ball_spp, options.seed);
    studio_scene = MakeBallScene(studio, options.ball_size, options.ball_spp, options.seed);
  }
  FitContext context;
  std::mutex mutex;
  AccuracySummary summary;
  summary.items = static_cast<int>(owned.size());
  int finished = 0;
  Report(options.progress, {"accuracy", 0, summary.items, "items"});

  auto run_item = [&](int64_t owned_index) {
    if (options.interrupt && options.interrupt->load()) return false;
    const size_t index = owned[owned_index];
    const AccuracyItem& it = all_items[index];
    const BatchItem& batch_item = manifest.items[index];
    const std::string label = ConfigLabel(it.rig, it.order);
    const std::string folder = MaterialFolderName(it.material);
    const std::string dir = options.out_dir + "/sessions/" + label + "/" + folder;
    if (ReadItemResult(options.out_dir, manifest, batch_item).is_object()) {
      std::lock_guard<std::mutex> lock(mutex);
      ++summary.reused;
      Report(options.progress, {"accuracy", ++finished, summary.items, "items"});
      return true;
    }
    const RunningMarker running(options.out_dir, batch_item);
    nlohmann::json row = {{"rig", RigLabel(it.rig)},   {"order", it.order},
                          {"preset", options.preset}, {"material", it.material},
                          {"folder", folder},         {"device", MaterialDevice(it.material)},
                          {"session", dir}};
    try {
      if (!fs::exists(SessionPath(dir, kZonalFile))) {
        VirtualCaptureArgs args;
        args.rig = rigs.at(it.rig);
        args.preset_name = options.preset;
        args.material_spec = it.material;
        args.seed = options.seed;
        args.job.out_dir = dir;
        args.job.order = it.order;
        args.job.resume = SessionFolder::Exists(dir);
        args.job.interrupt = options.interrupt;
        const VirtualCaptureOutcome outcome = RunVirtualCapture(args);
        if (!outcome.result.complete) return false;  // interrupted: resumable
      }
      const nlohmann::json session_report = ReadJsonOrNull(SessionPath(dir, kReportFile));
      if (session_report.is_object()) {
        row["rig_time_s"] = session_report.value("capture_time_model_s", nlohmann::json(nullptr));
      }
      FitSessionOptions fit;
      fit.model = "auto";
      fit.auto_candidates = options.candidates;
      fit.prior_path = prior_path;
      const std::string name = MaterialShortName(it.material);
      const bool in_prior = prior.MaterialIndex(name) >= 0;
      if (options.leave_one_out && in_prior) fit.prior.exclude = {name};
      const FitSessionOutcome outcome = FitSession(dir, fit, &context);
      const nlohmann::json& report = outcome.report;
      const nlohmann::json& choice = report["auto"];
      row["recommended"] = choice["recommended"];
      row["why"] = choice["why"];
      row["cv"] = choice["candidates"];
      row["leave_one_out"] = options.leave_one_out && in_prior;
      row["excluded"] = report["model"] == "prior" ? report["params"]["excluded"]
                                                   : nlohmann::json(fit.prior.exclude);
      // Every candidate's errors (fit_session.cc wrote them per candidate).
      nlohmann::json errors = nlohmann::json::object();
      for (const auto& [model, e] : choice["errors_against_truth"].items()) {
        errors[model] = {{"hemisphere", e["error_ngan"]["hemisphere"]},
                         {"theta_80", e["error_ngan"]["theta_80"]},
                         {"zone", e["error_ngan"]["zone"]},
                         {"hemisphere_pooled", e["error_cosine_l2"]},
                         {"theta_80_pooled", e["error_cosine_l2_80"]},
                         {"zone_pooled", e["error_in_zone"]}};
      }
      errors["recommended"] = errors[report["model"].get<std::string>()];
      row["errors"] = errors;
      row["residual_in_zone"] = report["residual"]["relative_residual"];
      row["fit_time_s"] = report["fit_time_s"];
      row["selection_time_s"] = choice.value("selection_time_s", nlohmann::json(nullptr));
      // The prior's fit report also says what it left out (leave-one-out check).
      const nlohmann::json prior_report =
          ReadJsonOrNull(SessionPath(dir, FitReportFileName("prior")));
      if (prior_report.is_object() && prior_report.contains("params")) {
        row["prior_excluded"] = prior_report["params"].value("excluded", nlohmann::json::array());
        row["prior_fit_time_s"] = prior_report["fit_time_s"];
      } else if (report["model"] == "prior") {
        row["prior_excluded"] = report["params"]["excluded"];
        row["prior_fit_time_s"] = report["fit_time_s"];
      }
      if (options.images && outcome.truth) {
        row["image_error"] = {
            {"sky", Num(BallError(*outcome.model, *outcome.truth, *sky_scene))},
            {"studio", Num(BallError(*outcome.model, *outcome.truth, *studio_scene))}};
      }
      if (const auto n = ngan.find(name); n != ngan.end() && MaterialDevice(it.material) == "merl") {
        row["ngan"] = {{"hemisphere", n->second.first}, {"theta_80", n->second.second}};
      }
    } catch (const InputError& e) {
      row["failure"] = e.what();
    } catch (const NumericalError& e) {
      row["failure"] = e.what();
    } catch (const DeviceError& e) {
      row["failure"] = e.what();
    }
    WriteItemResult(options.out_dir, manifest, batch_item, row);
    std::lock_guard<std::mutex> lock(mutex);
    ++summary.computed;
    summary.failed += row.contains("failure");
    Report(options.progress, {"accuracy", ++finished, summary.items, "items"});
    return true;
  };
  ParallelForEach(static_cast<int64_t>(owned.size()), options.parallel_items, run_item);
  // A shard leaves the tables to the merge (`zbrdf batch merge DIR`).
  AccuracySummary reduced = options.shard.IsWhole() ? ReduceAccuracy(options.out_dir) : AccuracySummary{};
  reduced.items = summary.items;
  reduced.computed = summary.computed;
  reduced.reused = summary.reused;
  reduced.failed = summary.failed;
  reduced.interrupted = finished < summary.items;
  return reduced;
}

AccuracySummary ReduceAccuracy(const std::string& out_dir) {
  AccuracySummary result;
  std::vector<nlohmann::json> rows;
  const std::string items_dir = out_dir + "/items";
  if (fs::exists(out_dir + "/" + kManifestFile)) {
    // A batch: its items' results, for the manifest's options, in the order of their files.
    const BatchManifest manifest = ReadManifest(out_dir, "accuracy");
    std::vector<BatchItem> items = manifest.items;
    std::sort(items.begin(), items.end(),
              [](const BatchItem& a, const BatchItem& b) { return a.result < b.result; });
    for (const BatchItem& item : items) {
      nlohmann::json j = ReadItemResult(out_dir, manifest, item);
      if (!j.is_object()) continue;
      j.erase("batch_options");
      rows.push_back(std::move(j));
    }
  } else if (fs::exists(items_dir)) {
    std::vector<std::string> files;
    for (const auto& entry : fs::recursive_directory_iterator(items_dir)) {
      if (entry.path().extension() == ".json") files.push_back(entry.path().string());
    }
    std::sort(files.begin(), files.end());
    for (const std::string& f : files) {
      nlohmann::json j = ReadJsonOrNull(f);
      if (j.is_object()) rows.push_back(std::move(j));
    }
  }
  // Groups: (rig, order, device).
  std::map<std::tuple<std::string, int, std::string>, std::vector<const nlohmann::json*>> groups;
  for (const nlohmann::json& r : rows) {
    groups[{r.value("rig", std::string()), r.value("order", 0), r.value("device", std::string())}]
        .push_back(&r);
  }
  const std::vector<std::string> methods = {"recommended", "prior", "dbrdf", "ggx"};
  nlohmann::json summaries = nlohmann::json::array();
  std::string md;
  char line[512];
  for (const auto& [key, group] : groups) {
    const auto& [rig, order, device] = key;
    nlohmann::json s = {{"rig", rig}, {"order", order}, {"device", device}};
    int ok = 0, failed = 0;
    std::map<std::string, std::vector<double>> full, e80, zone, full_pooled, e80_pooled;
    std::vector<double> sky, studio, residual, rig_time, fit_time, prior_time, ngan_full, ngan_80;
    std::map<std::string, int> recommended_count;
    int above_one = 0, below_ngan = 0, with_ngan = 0;
    std::vector<std::string> worst;
    std::vector<PlotSeries> cdf;
    std::vector<BarItem> bars;
    for (const nlohmann::json* r : group) {
      if (r->contains("failure")) {
        ++failed;
        continue;
      }
      ++ok;
      recommended_count[(*r)["recommended"].get<std::string>()]++;
      for (const std::string& m : methods) {
        const nlohmann::json& e = (*r)["errors"].value(m, nlohmann::json(nullptr));
        if (!e.is_object()) continue;
        auto take = [&](const char* k, std::map<std::string, std::vector<double>>& into) {
          if (e.value(k, nlohmann::json(nullptr)).is_number()) into[m].push_back(e[k].get<double>());
        };
        take("hemisphere", full);
        take("theta_80", e80);
        take("zone", zone);
        take("hemisphere_pooled", full_pooled);
        take("theta_80_pooled", e80_pooled);
      }
      const nlohmann::json& rec = (*r)["errors"]["recommended"];
      const double rec_full = rec.value("hemisphere", nlohmann::json(NAN)).is_number()
                                  ? rec["hemisphere"].get<double>()
                                  : NAN;
      if (rec_full > 1.0) {
        ++above_one;
        worst.push_back((*r)["material"].get<std::string>());
      }
      if (r->contains("ngan")) {
        ++with_ngan;
        const double n_full = (*r)["ngan"]["hemisphere"].get<double>();
        ngan_full.push_back(n_full);
        ngan_80.push_back((*r)["ngan"]["theta_80"].get<double>());
        below_ngan += rec_full < n_full;
        bars.push_back({MaterialShortName((*r)["material"].get<std::string>()), rec_full, n_full});
      } else {
        bars.push_back({MaterialShortName((*r)["material"].get<std::string>()), rec_full, NAN});
      }
      if (r->contains("image_error")) {
        const nlohmann::json& im = (*r)["image_error"];
        if (im["sky"].is_number()) sky.push_back(im["sky"].get<double>());
        if (im["studio"].is_number()) studio.push_back(im["studio"].get<double>());
      }
      auto num = [&](const char* k, std::vector<double>& into) {
        if (r->value(k, nlohmann::json(nullptr)).is_number()) into.push_back((*r)[k].get<double>());
      };
      num("residual_in_zone", residual);
      num("rig_time_s", rig_time);
      num("fit_time_s", fit_time);
      num("prior_fit_time_s", prior_time);
    }
    s["materials"] = ok;
    s["failed"] = failed;
    nlohmann::json per = nlohmann::json::object();
    for (const std::string& m : methods) {
      per[m] = {{"median_hemisphere", Num(Median(full[m]))},
                {"median_theta_80", Num(Median(e80[m]))},
                {"median_zone", Num(Median(zone[m]))},
                {"median_hemisphere_pooled", Num(Median(full_pooled[m]))},
                {"median_theta_80_pooled", Num(Median(e80_pooled[m]))},
                {"count", full[m].size()}};
      if (!full[m].empty()) cdf.push_back({m, full[m]});
    }
    if (!ngan_full.empty()) {
      per["ngan2005"] = {{"median_hemisphere", Num(Median(ngan_full))},
                         {"median_theta_80", Num(Median(ngan_80))},
                         {"count", ngan_full.size()}};
      cdf.push_back({"ngan2005 (dense)", ngan_full});
    }
    s["methods"] = per;
    s["recommended_models"] = recommended_count;
    s["recommended_above_1"] = above_one;
    s["recommended_above_1_materials"] = worst;
    s["below_ngan"] = below_ngan;
    s["with_ngan"] = with_ngan;
    s["median_image_error_sky"] = Num(Median(sky));
    s["median_image_error_studio"] = Num(Median(studio));
    s["median_residual_in_zone"] = Num(Median(residual));
    s["median_rig_time_s"] = Num(Median(rig_time));
    s["median_fit_time_s"] = Num(Median(fit_time));
    s["median_prior_fit_time_s"] = Num(Median(prior_time));
    summaries.push_back(s);
    const std::string tag = rig + "-o" + std::to_string(order) + "-" + device;
    WriteErrorCdfPlot(out_dir + "/cdf-" + tag + ".png",
                      "hemisphere error CDF, " + rig + " order " + std::to_string(order) + ", " +
                          device + " (" + std::to_string(ok) + " materials)",
                      cdf);
    WriteErrorBarPlot(out_dir + "/bars-" + tag + ".png",
                      "hemisphere error of the recommended fit, " + rig + " order " +
                          std::to_string(order) + ", " + device,
                      bars);
    // Markdown.
    std::snprintf(line, sizeof(line), "\n### %s, order %d, %s (%d materials%s)\n\n", rig.c_str(),
                  order, device.c_str(), ok, failed ? (", " + std::to_string(failed) + " failed").c_str() : "");
    md += line;
    md += "| method | hemisphere | theta <= 80 deg | in the zone | hemisphere (pooled) | theta <= 80 (pooled) |\n";
    md += "|---|---|---|---|---|---|\n";
    auto cell = [](const nlohmann::json& v) {
      char b[32] = "-";
      if (v.is_number()) std::snprintf(b, sizeof(b), "%.3f", v.get<double>());
      return std::string(b);
    };
    for (const auto& [m, p] : per.items()) {
      md += "| " + m + " | " + cell(p["median_hemisphere"]) + " | " + cell(p["median_theta_80"]) +
            " | " + cell(p.value("median_zone", nlohmann::json(nullptr))) + " | " +
            cell(p.value("median_hemisphere_pooled", nlohmann::json(nullptr))) + " | " +
            cell(p.value("median_theta_80_pooled", nlohmann::json(nullptr))) + " |\n";
    }
    std::snprintf(line, sizeof(line),
                  "\nRecommended fit above 1.0: %d; below Ngan's best dense fit: %d of %d; image "
                  "error (ball, relative RMSE) median %s under the sky, %s in the studio; in-zone "
                  "residual median %s; rig time median %s s; fit time median %s s (prior alone %s s).\n",
                  above_one, below_ngan, with_ngan, cell(s["median_image_error_sky"]).c_str(),
                  cell(s["median_image_error_studio"]).c_str(),
                  cell(s["median_residual_in_zone"]).c_str(), cell(s["median_rig_time_s"]).c_str(),
                  cell(s["median_fit_time_s"]).c_str(), cell(s["median_prior_fit_time_s"]).c_str());
    md += line;
  }
  nlohmann::json all_rows = nlohmann::json::array();
  for (const nlohmann::json& r : rows) all_rows.push_back(r);
  result.table = {{"items", all_rows}, {"summary", summaries}};
  WriteFileAtomically(out_dir + "/accuracy.json", result.table.dump(2) + "\n");
  WriteFileAtomically(out_dir + "/accuracy.md", md);
  // CSV: one row per item.
  std::string csv =
      "rig,order,device,material,recommended,leave_one_out,hemisphere,theta_80,zone,"
      "prior_hemisphere,prior_theta_80,dbrdf_hemisphere,dbrdf_theta_80,ggx_hemisphere,"
      "ggx_theta_80,ngan_hemisphere,ngan_theta_80,image_sky,image_studio,residual_in_zone,"
      "rig_time_s,fit_time_s,failure\n";
  auto v = [](const nlohmann::json& j) {
    char b[32] = "";
    if (j.is_number()) std::snprintf(b, sizeof(b), "%.6g", j.get<double>());
    return std::string(b);
  };
  for (const nlohmann::json& r : rows) {
    const nlohmann::json e = r.value("errors", nlohmann::json::object());
    auto err = [&](const char* m, const char* k) {
      return e.contains(m) ? v(e[m].value(k, nlohmann::json(nullptr))) : std::string();
    };
    const nlohmann::json ng = r.value("ngan", nlohmann::json::object());
    const nlohmann::json im = r.value("image_error", nlohmann::json::object());
    std::string failure = r.value("failure", std::string());
    std::replace(failure.begin(), failure.end(), '"', '\'');
    csv += r.value("rig", std::string()) + "," + std::to_string(r.value("order", 0)) + "," +
           r.value("device", std::string()) + ",\"" + r.value("material", std::string()) + "\"," +
           r.value("recommended", std::string()) + "," +
           (r.value("leave_one_out", false) ? "yes" : "no") + "," +
           err("recommended", "hemisphere") + "," + err("recommended", "theta_80") + "," +
           err("recommended", "zone") + "," + err("prior", "hemisphere") + "," +
           err("prior", "theta_80") + "," + err("dbrdf", "hemisphere") + "," +
           err("dbrdf", "theta_80") + "," + err("ggx", "hemisphere") + "," +
           err("ggx", "theta_80") + "," + v(ng.value("hemisphere", nlohmann::json(nullptr))) + "," +
           v(ng.value("theta_80", nlohmann::json(nullptr))) + "," +
           v(im.value("sky", nlohmann::json(nullptr))) + "," +
           v(im.value("studio", nlohmann::json(nullptr))) + "," +
           v(r.value("residual_in_zone", nlohmann::json(nullptr))) + "," +
           v(r.value("rig_time_s", nlohmann::json(nullptr))) + "," +
           v(r.value("fit_time_s", nlohmann::json(nullptr))) + ",\"" + failure + "\"\n";
  }
  WriteFileAtomically(out_dir + "/accuracy.csv", csv);
  return result;
}

}  // namespace zbrdf
