// `zbrdf prior build` over many materials, whole or as a batch (tools/batch.h, docs/cluster.md):
// a lab's library of thousands of measured materials is tabulated by shards, one item per
// material, and one reduce step assembles the prior file.
//
// Sources are listed without being read (a folder of 33 MB MERL tables is only listed), and each
// shard reads only its own materials. A batch folder (default: "<out>.batch/") holds the
// manifest and, per material, items/<id>.json (name, source, or the failure) and items/<id>.f32
// (its atoms, BuildPrior's values as raw little-endian floats). ReducePriorBuild writes the same
// prior file a whole `prior build` writes.
#pragma once

#include <string>
#include <vector>

#include "basis/progress.h"
#include "brdf/brdf_prior.h"
#include "brdf/tabulated_brdf.h"
#include "tools/batch.h"

namespace zbrdf {

// A material of a prior build, not read yet. source: "merl:NAME" / "rgl:NAME" (bundled), a file
// path (.binary, .json, .bsdf), or a material spec.
struct PriorSourceRef {
  std::string name, source;
};

// The materials of --from items: merl:* / rgl:* (a bundled set), a spec, a file, or a folder of
// files (sorted by name), minus those named in `exclude`. Throws InputError naming an item that
// is none of these, or a folder without BRDF files.
std::vector<PriorSourceRef> CollectPriorSources(const std::vector<std::string>& from,
                                                const std::vector<std::string>& exclude = {});
// Reads one (InputError naming the file or spec on failure).
PriorSource LoadPriorSource(const PriorSourceRef& ref);

struct PriorBuildOptions {
  std::vector<std::string> from, exclude;
  HalfDiffGrid grid;
  std::string out;                        // the prior file
  std::string batch_dir;                  // empty: out + ".batch"
  Shard shard;
  std::vector<std::string> command_args;  // the command line (after `prior`), for the manifest
  ProgressCallback progress;

  std::string BatchDir() const { return batch_dir.empty() ? out + ".batch" : batch_dir; }
};

BatchManifest PriorBuildManifest(const PriorBuildOptions& options);

// Writes the manifest (PrepareManifest) and tabulates the shard's materials that have no item
// yet. Returns how many it tabulated.
int RunPriorBuildShard(const PriorBuildOptions& options);

// Assembles the prior from every item of the batch in batch_dir and writes the file the manifest
// names. Throws InputError listing missing items (with what to run) or a material's failure.
BrdfPrior ReducePriorBuild(const std::string& batch_dir);

}  // namespace zbrdf
