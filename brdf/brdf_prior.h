// A prior over isotropic BRDFs learned from measured materials: the library of their tables.
//
// Why a library and not a few principal components: fitted to the zonal data of the thesis rig
// (about half the hemisphere, order 8), a non-negative combination of measured tables
// extrapolates better than a regularized log-PCA model and never blows up where the zone does
// not look (docs/prior.md has the measurements). Each material contributes three atoms, its R,
// G and B tables on a HalfDiffGrid (brdf/tabulated_brdf.h); fitting/prior_fit.h combines atoms
// with non-negative weights per channel. A non-negative combination of reciprocal, bilaterally
// symmetric tables is reciprocal and symmetric, and its tails are bounded by the library's.
//
// The file (OpenEXR, one part, ZIP-compressed): an image grid.size() pixels wide and one row
// per atom, channel "f" in HALF (f_r in 1/sr divided by the atom's scale, which is 1 unless a
// value exceeds half's range). Attributes: zbrdf.format "zbrdf-prior-v1", zbrdf.grid (three ints
// as text "nh nd np"), zbrdf.atoms (JSON list of {"material", "channel", "scale", "source"}),
// zbrdf.info (JSON: how it was built). Half precision stores f_r to 5e-4 relative, below any
// measurement's accuracy; the 100 MERL materials make a 4-5 MB file.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "basis/progress.h"
#include "brdf/brdf.h"
#include "brdf/tabulated_brdf.h"

namespace zbrdf {

struct BrdfPrior {
  HalfDiffGrid grid;
  std::vector<std::string> materials;  // one name per material
  std::vector<std::string> sources;    // where each was read from (spec or path)
  // grid.size() x 3 materials.size(): column 3 k + c is channel c of material k.
  Eigen::MatrixXf atoms;
  nlohmann::json info = nlohmann::json::object();

  int material_count() const { return static_cast<int>(materials.size()); }
  // FNV-1a over grid, names and atom values: the key of caches derived from the prior.
  uint64_t Hash() const;
  // Index of a material by name, or -1.
  int MaterialIndex(const std::string& name) const;
};

// One material of a prior: its name (unique in the prior), the BRDF, and where it came from.
struct PriorSource {
  std::string name;
  std::shared_ptr<const Brdf> brdf;
  std::string source;
};

// Tabulates every source on the grid (TabulateBrdf). Throws InputError for no sources, a
// duplicate name, or a source whose table is zero everywhere or not finite (naming it).
BrdfPrior BuildPrior(const std::vector<PriorSource>& sources, const HalfDiffGrid& grid,
                     const ProgressCallback& progress = nullptr);

// BuildPrior's two steps, for builds split over processes (tools/prior_build.h):
// one material's atoms (grid.size() x 3, column-major: channel c at [c * grid.size() + n]),
// with BuildPrior's checks and errors;
std::vector<float> PriorAtoms(const PriorSource& source, const HalfDiffGrid& grid);
// and the prior from every material's name, source and atoms, in order (InputError for none, a
// duplicate name or atoms of the wrong size).
BrdfPrior AssemblePrior(const HalfDiffGrid& grid, const std::vector<std::string>& names,
                        const std::vector<std::string>& sources,
                        const std::vector<std::vector<float>>& atoms);

// Throws InputError naming the file if it cannot be written.
void WritePriorFile(const std::string& path, const BrdfPrior& prior);
// Throws InputError naming the file and the problem (not OpenEXR, not a prior, a missing or
// malformed attribute, sizes that disagree, negative or non-finite values).
BrdfPrior ReadPriorFile(const std::string& path);

// The prior shipped with zbrdf: data/priors/merl100.exr under DataRoot(), built from the 100
// bundled MERL networks by `zbrdf prior build` (docs/prior.md).
std::string DefaultPriorPath();

}  // namespace zbrdf
