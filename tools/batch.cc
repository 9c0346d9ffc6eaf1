#include "tools/batch.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <set>

#include "basis/atomic_file.h"
#include "basis/error.h"
#include "tools/json_file.h"

namespace zbrdf {
namespace fs = std::filesystem;
namespace {

constexpr char kManifestFormat[] = "zbrdf batch manifest 1";

std::string HostName() {
  char name[256] = {};
  if (::gethostname(name, sizeof(name) - 1) != 0) return "unknown";
  return name;
}

std::string RunningPath(const std::string& dir, const BatchItem& item) {
  return dir + "/running/" + item.id + ".json";
}

bool ProcessAlive(long pid) {
  if (pid <= 0) return false;
  return ::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM;
}

}  // namespace

std::vector<size_t> Shard::ItemsOf(size_t item_count) const {
  std::vector<size_t> items;
  for (size_t k = 0; k < item_count; ++k) {
    if (Owns(k)) items.push_back(k);
  }
  return items;
}

std::string Shard::ToString() const { return std::to_string(index) + "/" + std::to_string(count); }

Shard Shard::Parse(const std::string& text) {
  const size_t slash = text.find('/');
  auto bad = [&]() {
    return InputError("--shard '" + text +
                      "' is not I/N with 0 <= I < N (e.g. --shard 0/4 runs the first of 4 shards)");
  };
  if (slash == std::string::npos || slash == 0 || slash + 1 >= text.size()) throw bad();
  const std::string a = text.substr(0, slash), b = text.substr(slash + 1);
  auto digits = [](const std::string& s) {
    return !s.empty() && s.size() <= 6 && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  if (!digits(a) || !digits(b)) throw bad();
  Shard shard{std::atoi(a.c_str()), std::atoi(b.c_str())};
  if (shard.count < 1 || shard.index >= shard.count) throw bad();
  return shard;
}

nlohmann::json BatchManifest::ToJson() const {
  nlohmann::json list = nlohmann::json::array();
  for (const BatchItem& item : items) list.push_back({{"id", item.id}, {"result", item.result}});
  return {{"format", kManifestFormat}, {"command", command}, {"args", args},
          {"options", options},        {"items", list}};
}

BatchManifest BatchManifest::FromJson(const nlohmann::json& j, const std::string& where) {
  if (!j.is_object() || j.value("format", std::string()) != kManifestFormat ||
      !j.contains("items") || !j["items"].is_array()) {
    throw InputError(where + " is not a zbrdf batch manifest (" + kManifestFormat +
                     "); it is written by `zbrdf fit-all`, `accuracy` or `bench` in their --out folder");
  }
  BatchManifest m;
  m.command = j.value("command", std::string());
  if (j.contains("args") && j["args"].is_array()) {
    for (const auto& a : j["args"]) {
      if (a.is_string()) m.args.push_back(a.get<std::string>());
    }
  }
  m.options = j.value("options", nlohmann::json::object());
  std::set<std::string> ids;
  for (const auto& item : j["items"]) {
    if (!item.is_object() || !item.contains("id") || !item["id"].is_string() ||
        !item.contains("result") || !item["result"].is_string()) {
      throw InputError(where + ": an item without a string id and result: " + item.dump());
    }
    BatchItem b{item["id"].get<std::string>(), item["result"].get<std::string>()};
    if (b.id.empty() || b.id.find('/') != std::string::npos || b.result.empty() ||
        b.result.front() == '/' || b.result.find("..") != std::string::npos ||
        !ids.insert(b.id).second) {
      throw InputError(where + ": item '" + b.id +
                       "' has an empty, repeated or unsafe id or result path; rerun the command that "
                       "made the batch to write a new manifest");
    }
    m.items.push_back(std::move(b));
  }
  return m;
}

bool BatchManifest::SameWork(const BatchManifest& other) const {
  if (command != other.command || options != other.options || items.size() != other.items.size()) {
    return false;
  }
  for (size_t i = 0; i < items.size(); ++i) {
    if (items[i].id != other.items[i].id || items[i].result != other.items[i].result) return false;
  }
  return true;
}

void PrepareManifest(const std::string& dir, const BatchManifest& manifest, const Shard& shard) {
  fs::create_directories(dir);
  const std::string path = dir + "/" + kManifestFile;
  if (shard.IsWhole()) {
    const nlohmann::json existing = ReadJsonOrNull(path);
    // Unchanged work keeps its file (a rerun does not touch it).
    if (existing.is_object()) {
      try {
        if (BatchManifest::FromJson(existing, path).SameWork(manifest)) return;
      } catch (const InputError&) {
        // Replaced below.
      }
    }
    WriteFileAtomically(path, manifest.ToJson().dump(1) + "\n");
    return;
  }
  const nlohmann::json existing = ReadJsonOrNull(path);
  if (existing.is_null()) {
    // The first shard to start writes it (every shard computes the same manifest; the rename
    // is atomic, so concurrent shards leave one whole file).
    WriteFileAtomically(path, manifest.ToJson().dump(1) + "\n");
    return;
  }
  const BatchManifest stored = BatchManifest::FromJson(existing, path);
  if (!stored.SameWork(manifest)) {
    throw InputError("shard " + shard.ToString() + ": " + path + " describes other work (`zbrdf " +
                     stored.command + "` with " + std::to_string(stored.items.size()) +
                     " items); run every shard with the same options as the command that wrote it, "
                     "or use another --out folder");
  }
}

BatchManifest ReadManifest(const std::string& dir) {
  const std::string path = dir + "/" + kManifestFile;
  if (!fs::exists(path)) {
    throw InputError(path + " does not exist: " + dir +
                     " is not a batch folder (one is written by `zbrdf fit-all`, `accuracy` or `bench` with "
                     "--out DIR)");
  }
  const nlohmann::json j = ReadJsonOrNull(path);
  if (j.is_null()) throw InputError(path + " is not valid JSON; rerun the command that made the batch");
  return BatchManifest::FromJson(j, path);
}

BatchManifest ReadManifest(const std::string& dir, const std::string& command) {
  BatchManifest manifest = ReadManifest(dir);
  if (manifest.command != command) {
    throw InputError(dir + "/manifest.json is a `zbrdf " + manifest.command + "` batch, not " +
                     command + "; merge it with `zbrdf batch merge " + dir + "`");
  }
  return manifest;
}

nlohmann::json ReadItemResult(const std::string& dir, const BatchManifest& manifest,
                              const BatchItem& item) {
  nlohmann::json j = ReadJsonOrNull(dir + "/" + item.result);
  if (!j.is_object() || !j.contains("batch_options") || j["batch_options"] != manifest.options) {
    return nullptr;
  }
  return j;
}

void WriteItemResult(const std::string& dir, const BatchManifest& manifest, const BatchItem& item,
                     nlohmann::json result) {
  result["batch_options"] = manifest.options;
  const std::string path = dir + "/" + item.result;
  fs::create_directories(fs::path(path).parent_path());
  WriteFileAtomically(path, result.dump(2) + "\n");
  std::error_code error;
  fs::remove(RunningPath(dir, item), error);
}

RunningMarker::RunningMarker(const std::string& dir, const BatchItem& item)
    : path_(RunningPath(dir, item)) {
  nlohmann::json marker = {
      {"host", HostName()},
      {"pid", static_cast<long>(::getpid())},
      {"started_unix_s", std::chrono::duration<double>(
                             std::chrono::system_clock::now().time_since_epoch()).count()}};
  for (const char* var : {"SLURM_JOB_ID", "SLURM_ARRAY_JOB_ID", "SLURM_ARRAY_TASK_ID"}) {
    if (const char* v = std::getenv(var); v && *v) marker[var] = v;
  }
  std::error_code error;
  fs::create_directories(fs::path(path_).parent_path(), error);
  try {
    WriteFileAtomically(path_, marker.dump() + "\n");
  } catch (const FileWriteError&) {
    path_.clear();  // the status is only informative: the work goes on without it
  }
}

RunningMarker::~RunningMarker() {
  if (path_.empty()) return;
  std::error_code error;
  fs::remove(path_, error);
}

const char* ItemStateName(ItemState state) {
  switch (state) {
    case ItemState::kDone: return "done";
    case ItemState::kFailed: return "failed";
    case ItemState::kRunning: return "running";
    case ItemState::kStale: return "stale";
    case ItemState::kPending: return "pending";
  }
  return "?";
}

std::vector<ItemStatus> BatchStatus(const std::string& dir, int shard_count,
                                    const std::vector<std::string>* live_slurm_jobs) {
  const BatchManifest manifest = ReadManifest(dir);
  if (shard_count < 1) throw InputError("the shard count must be at least 1");
  const std::string host = HostName();
  std::vector<ItemStatus> out;
  for (size_t k = 0; k < manifest.items.size(); ++k) {
    ItemStatus s;
    s.item = manifest.items[k];
    s.shard = static_cast<int>(k % shard_count);
    const nlohmann::json result = ReadItemResult(dir, manifest, s.item);
    if (result.is_object()) {
      s.state = result.contains("failure") ? ItemState::kFailed : ItemState::kDone;
    } else if (const nlohmann::json marker = ReadJsonOrNull(RunningPath(dir, s.item));
               marker.is_object()) {
      s.running = marker;
      bool alive = true;
      if (marker.value("host", std::string()) == host) {
        alive = ProcessAlive(marker.value("pid", 0L));
      }
      if (alive && live_slurm_jobs && marker.contains("SLURM_JOB_ID")) {
        const std::string job = marker["SLURM_JOB_ID"].get<std::string>();
        std::string array_task;
        if (marker.contains("SLURM_ARRAY_JOB_ID") && marker.contains("SLURM_ARRAY_TASK_ID")) {
          array_task = marker["SLURM_ARRAY_JOB_ID"].get<std::string>() + "_" +
                       marker["SLURM_ARRAY_TASK_ID"].get<std::string>();
        }
        alive = std::find(live_slurm_jobs->begin(), live_slurm_jobs->end(), job) != live_slurm_jobs->end() ||
                (!array_task.empty() && std::find(live_slurm_jobs->begin(), live_slurm_jobs->end(),
                                                  array_task) != live_slurm_jobs->end());
      }
      s.state = alive ? ItemState::kRunning : ItemState::kStale;
    }
    out.push_back(std::move(s));
  }
  return out;
}

std::vector<int> ShardsWithMissingItems(const std::vector<ItemStatus>& status) {
  std::set<int> shards;
  for (const ItemStatus& s : status) {
    if (s.state == ItemState::kPending || s.state == ItemState::kStale) shards.insert(s.shard);
  }
  return {shards.begin(), shards.end()};
}

}  // namespace zbrdf
