// Batches as independent work items (docs/cluster.md): what `fit-all` and `accuracy` turn their
// options into, so that any number of processes, on one machine or as a Slurm job array
// (tools/slurm.h), can share the work and one reduce step builds the tables.
//
// A batch folder DIR holds:
//   DIR/manifest.json        the command, the command line that made it, and the ordered list of
//                            work items (id, result file), written before any work
//   DIR/<item result file>   one JSON object per finished item, written atomically; a rerun (or a
//                            resubmitted shard) skips items whose result exists, so a killed
//                            process redoes only the item it was in (and that item resumes from
//                            its session folder)
//   DIR/running/<id>.json    while an item runs: host, pid, Slurm job and start time
// Shard I of N (--shard I/N) owns the items whose manifest index k has k % N == I: every item
// belongs to exactly one shard, and the split does not depend on which items are done.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace zbrdf {

// "I/N" with 0 <= I < N, N >= 1. The default owns everything.
struct Shard {
  int index = 0, count = 1;
  bool Owns(size_t item_index) const { return static_cast<int>(item_index % count) == index; }
  // The indices this shard owns among item_count items, ascending.
  std::vector<size_t> ItemsOf(size_t item_count) const;
  bool IsWhole() const { return count == 1; }
  std::string ToString() const;
  // Throws InputError naming the text and the expected form.
  static Shard Parse(const std::string& text);
};

struct BatchItem {
  std::string id;      // unique in the batch; a file-name-safe string
  std::string result;  // result file, relative to the batch folder
};

struct BatchManifest {
  std::string command;             // "fit-all", "accuracy"
  std::vector<std::string> args;   // the command's flags, as given (without --shard/--executor)
  nlohmann::json options;          // what defines the items' results (compared on reruns)
  std::vector<BatchItem> items;

  nlohmann::json ToJson() const;
  static BatchManifest FromJson(const nlohmann::json& j, const std::string& where);
  // True when both describe the same work (command, options, items), whatever the flags' order.
  bool SameWork(const BatchManifest& other) const;
};

constexpr char kManifestFile[] = "manifest.json";

// Writes DIR/manifest.json for a whole (unsharded) run: replaces a manifest of other work (the
// table then lists this run's items). For a shard (count > 1) the manifest must exist and
// describe the same work: a shard never redefines the batch, and InputError says which command
// made DIR's manifest and what to do.
void PrepareManifest(const std::string& dir, const BatchManifest& manifest, const Shard& shard);

// Throws InputError when DIR has no readable manifest (names the file, says which commands make
// one), or, given `command`, when the manifest is another command's.
BatchManifest ReadManifest(const std::string& dir);
BatchManifest ReadManifest(const std::string& dir, const std::string& command);

// The item's result (a JSON object), or null when it is missing, unreadable, or was computed for
// other options than the manifest's (its "batch_options" differ: a rerun with other options
// recomputes it).
nlohmann::json ReadItemResult(const std::string& dir, const BatchManifest& manifest,
                              const BatchItem& item);
// Writes the result with "batch_options" = the manifest's options, atomically (creating
// folders), and removes the item's running marker.
void WriteItemResult(const std::string& dir, const BatchManifest& manifest, const BatchItem& item,
                     nlohmann::json result);

// Marks an item as running in this process (DIR/running/<id>.json); RAII removes the marker when
// the item ends without a result (interrupted, or an exception).
class RunningMarker {
 public:
  RunningMarker(const std::string& dir, const BatchItem& item);
  ~RunningMarker();
  RunningMarker(const RunningMarker&) = delete;
  RunningMarker& operator=(const RunningMarker&) = delete;

 private:
  std::string path_;
};

enum class ItemState { kDone, kFailed, kRunning, kStale, kPending };
const char* ItemStateName(ItemState state);

struct ItemStatus {
  BatchItem item;
  int shard = 0;  // under the shard count given to BatchStatus
  ItemState state = ItemState::kPending;
  nlohmann::json running;  // the marker's content when running or stale
};

// Every item's state. A marker whose process is gone (same host, pid not running) is kStale;
// a marker from another host counts as running unless `live_slurm_jobs` is given and holds no
// job of the marker (then kStale). A result with a "failure" key is kFailed.
std::vector<ItemStatus> BatchStatus(const std::string& dir, int shard_count,
                                    const std::vector<std::string>* live_slurm_jobs = nullptr);

// The shards (under shard_count) that own an item without a result.
std::vector<int> ShardsWithMissingItems(const std::vector<ItemStatus>& status);

}  // namespace zbrdf
