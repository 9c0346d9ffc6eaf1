// Measured materials as small neural networks ("nbrdf-mlp-v1"; data/materials/README.md): the
// 100 MERL isotropic materials (Matusik et al. 2003) as 6-21-21-3 multilayer perceptrons trained
// by Sztrajman, Rainer, Ritschel & Weyrich ("Neural BRDF Representation and Importance
// Sampling", CGF 2021; MIT license). Cite both works wherever results on them are shown.
//
// Evaluated in float64 per the README's recipe: h = normalize(w_i + w_o); d = w_i rotated by
// -phi_h about z, then by -theta_h about y; x = (sin theta_h, 0, cos theta_h, d.x, d.y, d.z);
// y = W3 relu(W2 relu(W1 x + b1) + b2) + b3; f_r = max(exp(y) - 1, 0) per channel. The rotations
// are applied with cos/sin of phi_h and theta_h taken from h directly (no trigonometric calls),
// which is the same map up to rounding.
//
// Neither reciprocal nor energy conserving by construction. Sampled with a HalfVectorProxySampler
// fitted at load. EvalBatch evaluates blocks of 64 pairs, each layer on 16 pairs at a time kept
// in SIMD registers (AVX2 where the CPU has it, chosen at run time), summed in the same order
// as Eval; all methods are const and thread-safe, so callers may split a large batch across
// threads.
#pragma once

#include <array>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "brdf/brdf.h"
#include "brdf/proxy_sampler.h"

namespace zbrdf {

// The weights of one network file.
struct NbrdfNetwork {
  struct Layer {
    int in = 0, out = 0;
    std::vector<double> weights;  // row-major in x out: weights[i * out + j]
    std::vector<double> bias;     // out
  };
  std::string material;         // the file's "material" field
  std::array<Layer, 3> layers;  // 6 -> hidden -> hidden -> 3
};

// Reads and validates a network file. Throws InputError naming the file and the field at fault
// (missing, wrong format tag, sizes that do not chain 6 -> ... -> 3, non-finite numbers).
// Hidden layers may be 1 to 256 wide.
NbrdfNetwork ReadNbrdfNetwork(const std::string& path);

// Names of a bundled set's materials (data/materials/SET/NAME.json under DataRoot()), sorted:
// "merl" (the 100 MERL materials) or "rgl" (18 materials of the RGL database, Dupuy & Jakob
// 2018, measured on another device: the validation set of docs/prior.md).
std::vector<std::string> BundledMaterialNames(const std::string& set = "merl");

// A layer's weights in one precision, transposed (out x in, so that a neuron's weights are
// contiguous), and its biases: what NbrdfBrdf's evaluation loops read.
template <typename T>
struct LayerWeights {
  int in = 0, out = 0;
  std::vector<T> w_t, bias;
};

class NbrdfBrdf final : public ProxySampledBrdf {
 public:
  // spec: what Spec() returns ("merl:NAME" or "file:PATH").
  NbrdfBrdf(NbrdfNetwork network, std::string spec);
  // A bundled material, e.g. "blue-acrylic" (Spec() "merl:blue-acrylic"; "rgl:cardboard" for
  // set "rgl"). Throws InputError for unknown names, suggesting close names and saying where
  // the list is. Each bundled file is read and its sampler fitted once per process.
  static std::unique_ptr<NbrdfBrdf> FromName(const std::string& name,
                                             const std::string& set = "merl");
  // A network file anywhere; Spec() is "file:" + path.
  static std::unique_ptr<NbrdfBrdf> FromFile(const std::string& path);

  Rgb Eval(const Vec3& w_i, const Vec3& w_o) const override;
  void EvalBatch(std::span<const Vec3> w_i, std::span<const Vec3> w_o,
                 std::span<Rgb> f) const override;
  // The layers in float32 (8 pairs per AVX2 register instead of 4): |f - EvalBatch's f| within
  // 1e-5 (1 + f), ~1e-6 measured, for the simulator's Monte Carlo sums (error ~5e-3).
  void EvalBatchSinglePrecision(std::span<const Vec3> w_i, std::span<const Vec3> w_o,
                                std::span<Rgb> f) const override;
  // The exponential (the network's output map) only for the channel asked, or all three for
  // luminance.
  void EvalChannelBatchSinglePrecision(std::span<const Vec3> w_i, std::span<const Vec3> w_o,
                                       int channel, std::span<double> value) const override;
  bool IsReciprocal() const override { return false; }
  bool IsEnergyConserving() const override { return false; }
  bool IsIsotropic() const override { return true; }  // fitted to isotropic MERL tables
  std::string Spec() const override { return spec_; }

  const NbrdfNetwork& network() const { return network_; }

 private:
  // With the proxy sampler fitted to an identical network earlier (null: fits it).
  NbrdfBrdf(NbrdfNetwork network, std::string spec,
            std::shared_ptr<const HalfVectorProxySampler> sampler);
  // Evaluates count pairs (at most one block) using scratch from EvalBatchIn: the network's
  // outputs y (row c: channel c of the pairs), and valid[k] false for pairs below the horizon.
  // channel >= 0: only that row of y is computed (the others hold stale values).
  template <typename T>
  const T* EvalBlock(const Vec3* w_i, const Vec3* w_o, int count, T* scratch, bool* valid,
                     int channel = -1) const;
  // Blocks of EvalBlock; `out(start, count, y, valid)` maps each block's outputs.
  template <typename T, typename Out>
  void EvalBatchIn(std::span<const Vec3> w_i, std::span<const Vec3> w_o, const Out& out,
                   int channel = -1) const;

  NbrdfNetwork network_;
  std::array<LayerWeights<double>, 3> weights_;
  std::array<LayerWeights<float>, 3> weights_float_;
  std::string spec_;
};

}  // namespace zbrdf
