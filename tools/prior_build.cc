#include "tools/prior_build.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>

#include "basis/atomic_file.h"
#include "basis/error.h"
#include "brdf/brdf_file.h"
#include "brdf/material_spec.h"
#include "brdf/nbrdf.h"
#include "tools/fit_all.h"

namespace zbrdf {
namespace fs = std::filesystem;
namespace {

// The readable BRDF files of a folder, by name: MERL tables, networks, RGL files.
std::vector<std::string> FilesIn(const std::string& dir) {
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string ext = entry.path().extension().string();
    if (entry.is_regular_file() && (ext == ".binary" || ext == ".json" || ext == ".bsdf")) {
      files.push_back(entry.path().string());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

bool IsBundled(const std::string& source, std::string* set, std::string* name) {
  for (const char* s : {"merl", "rgl"}) {
    const std::string prefix = std::string(s) + ":";
    if (source.rfind(prefix, 0) == 0 && !fs::exists(source)) {
      const std::string n = source.substr(prefix.size());
      const auto names = BundledMaterialNames(s);
      if (std::find(names.begin(), names.end(), n) != names.end()) {
        *set = s;
        *name = n;
        return true;
      }
    }
  }
  return false;
}

std::vector<float> ReadFloats(const std::string& path, size_t count) {
  std::ifstream in(path, std::ios::binary);
  std::vector<float> v(count);
  if (!in || !in.read(reinterpret_cast<char*>(v.data()), static_cast<std::streamsize>(count * 4)) ||
      in.peek() != std::char_traits<char>::eof()) {
    throw InputError(path + " is missing or not " + std::to_string(count) +
                     " floats; delete it and its .json and run the shard again");
  }
  return v;
}

}  // namespace

std::vector<PriorSourceRef> CollectPriorSources(const std::vector<std::string>& from,
                                                const std::vector<std::string>& exclude) {
  std::vector<PriorSourceRef> refs;
  for (const std::string& item : from) {
    if (item == "merl:*" || item == "rgl:*") {
      const std::string set = item.substr(0, item.find(':'));
      for (const std::string& name : BundledMaterialNames(set)) refs.push_back({name, set + ":" + name});
    } else if (fs::is_directory(item)) {
      const std::vector<std::string> files = FilesIn(item);
      if (files.empty()) {
        throw InputError("--from " + item + ": the folder holds no .binary, .json or .bsdf file");
      }
      for (const std::string& f : files) refs.push_back({fs::path(f).stem().string(), f});
    } else if (fs::exists(item)) {
      refs.push_back({fs::path(item).stem().string(), item});
    } else {
      MakeBrdf(item);  // a spec: checked now, so a typo fails before any work
      refs.push_back({MaterialShortName(item), item});
    }
  }
  const std::set<std::string> leave_out(exclude.begin(), exclude.end());
  std::erase_if(refs, [&](const PriorSourceRef& r) { return leave_out.count(r.name) > 0; });
  return refs;
}

PriorSource LoadPriorSource(const PriorSourceRef& ref) {
  std::string set, name;
  if (IsBundled(ref.source, &set, &name)) return {ref.name, NbrdfBrdf::FromName(name, set), ref.source};
  if (fs::exists(ref.source)) return {ref.name, ReadBrdfFile(ref.source).brdf, ref.source};
  return {ref.name, MakeBrdf(ref.source), ref.source};
}

BatchManifest PriorBuildManifest(const PriorBuildOptions& options) {
  const std::vector<PriorSourceRef> refs = CollectPriorSources(options.from, options.exclude);
  if (refs.empty()) throw InputError("prior: no materials to build it from");
  BatchManifest manifest;
  manifest.command = "prior";
  manifest.args = options.command_args;
  nlohmann::json sources = nlohmann::json::array();
  std::set<std::string> ids;
  for (const PriorSourceRef& r : refs) {
    sources.push_back({{"name", r.name}, {"source", r.source}});
    const std::string id = MaterialFolderName(r.name);
    if (!ids.insert(id).second) {
      throw InputError("prior: material name " + r.name + " appears twice (" + r.source +
                       "); names identify the materials a fit may leave out");
    }
    manifest.items.push_back({id, "items/" + id + ".json"});
  }
  manifest.options = {{"grid", options.grid.ToString()},
                      {"out", fs::absolute(options.out).lexically_normal().string()},
                      {"from", options.from},
                      {"sources", sources}};
  return manifest;
}

int RunPriorBuildShard(const PriorBuildOptions& options) {
  const BatchManifest manifest = PriorBuildManifest(options);
  const std::string dir = options.BatchDir();
  PrepareManifest(dir, manifest, options.shard);
  const nlohmann::json& sources = manifest.options["sources"];
  const std::vector<size_t> owned = options.shard.ItemsOf(manifest.items.size());
  int tabulated = 0;
  Report(options.progress, {"prior", 0, static_cast<long>(owned.size()), "materials"});
  for (size_t i = 0; i < owned.size(); ++i) {
    const size_t k = owned[i];
    const BatchItem& item = manifest.items[k];
    if (ReadItemResult(dir, manifest, item).is_object()) continue;
    const RunningMarker running(dir, item);
    const PriorSourceRef ref{sources[k]["name"].get<std::string>(), sources[k]["source"].get<std::string>()};
    nlohmann::json result = {{"name", ref.name}, {"source", ref.source}};
    std::vector<float> atoms;
    try {
      atoms = PriorAtoms(LoadPriorSource(ref), options.grid);
    } catch (const InputError& e) {  // the material's own failure: a result (the merge names it)
      result["failure"] = e.what();
    }
    if (!result.contains("failure")) {
      const std::string table = "items/" + item.id + ".f32";
      fs::create_directories(dir + "/items");
      WriteFileAtomically(dir + "/" + table,
                          std::string(reinterpret_cast<const char*>(atoms.data()), atoms.size() * 4));
      result["table"] = table;
      result["floats"] = atoms.size();
    }
    WriteItemResult(dir, manifest, item, result);
    ++tabulated;
    Report(options.progress, {"prior", static_cast<long>(i + 1), static_cast<long>(owned.size()), "materials"});
  }
  return tabulated;
}

BrdfPrior ReducePriorBuild(const std::string& batch_dir) {
  const BatchManifest manifest = ReadManifest(batch_dir, "prior");
  const std::string grid_text = manifest.options.value("grid", std::string());
  int nh = 0, nd = 0, np = 0;
  if (std::sscanf(grid_text.c_str(), "%d x %d x %d", &nh, &nd, &np) != 3) {
    throw InputError(batch_dir + "/manifest.json: grid '" + grid_text + "' is not NHxNDxNP");
  }
  const HalfDiffGrid grid(nh, nd, np);
  std::vector<std::string> names, sources, missing;
  std::vector<std::vector<float>> atoms;
  for (const BatchItem& item : manifest.items) {
    const nlohmann::json r = ReadItemResult(batch_dir, manifest, item);
    if (!r.is_object()) {
      missing.push_back(item.id);
      continue;
    }
    if (r.contains("failure")) throw InputError(r["failure"].get<std::string>());
    names.push_back(r["name"].get<std::string>());
    sources.push_back(r["source"].get<std::string>());
    atoms.push_back(ReadFloats(batch_dir + "/" + r["table"].get<std::string>(), 3 * static_cast<size_t>(grid.size())));
  }
  if (!missing.empty()) {
    throw InputError(std::to_string(missing.size()) + " of " + std::to_string(manifest.items.size()) +
                     " materials of the prior build in " + batch_dir + " are not tabulated yet (first: " +
                     missing.front() + "); see `zbrdf batch status " + batch_dir + "`, then resubmit");
  }
  BrdfPrior prior = AssemblePrior(grid, names, sources, atoms);
  prior.info["from"] = manifest.options["from"];
  const std::string out = manifest.options["out"].get<std::string>();
  if (fs::path(out).has_parent_path()) fs::create_directories(fs::path(out).parent_path());
  WritePriorFile(out, prior);
  return prior;
}

}  // namespace zbrdf
