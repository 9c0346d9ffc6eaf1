#include "brdf/nbrdf.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <type_traits>

#include "basis/cpu_features.h"
#include "basis/data_path.h"
#include "basis/error.h"
#include "basis/strings.h"

namespace zbrdf {
namespace {

constexpr int kInputs = 6;
constexpr int kOutputs = 3;
constexpr int kMaxHidden = 256;
constexpr const char* kNetworkFormat = "nbrdf-mlp-v1";

// Pairs per block of EvalBatch; a multiple of kTile and kFmaFloatTile.
constexpr int kBlock = 64;
// Pairs whose accumulators a layer keeps in registers at once: three neurons' four AVX2 vectors
// of doubles (or two of floats) ...
constexpr int kTile = 16;
// ... and in the single precision version with fused multiply-adds, four vectors of floats.
constexpr int kFmaFloatTile = 32;

// Tiles of `tile` pairs that hold `count` pairs.
constexpr int TilesFor(int count, int tile) { return (count + tile - 1) / tile; }

[[noreturn]] void FailNetworkFile(const std::string& path, const std::string& what) {
  throw InputError("network file " + path + ": " + what);
}

NbrdfNetwork::Layer ReadLayer(const std::string& path, const nlohmann::json& json, int index) {
  const std::string name = "layers[" + std::to_string(index) + "]";
  if (!json.is_object()) FailNetworkFile(path, name + " must be an object");
  NbrdfNetwork::Layer layer;
  for (const char* key : {"in", "out"}) {
    if (!json.contains(key) || !json[key].is_number_integer()) {
      FailNetworkFile(path, name + "." + key + " must be an integer");
    }
  }
  layer.in = json["in"].get<int>();
  layer.out = json["out"].get<int>();
  if (layer.in < 1 || layer.out < 1) {
    FailNetworkFile(path, name + " has in = " + std::to_string(layer.in) +
                              ", out = " + std::to_string(layer.out) + "; both must be >= 1");
  }
  const auto read_numbers = [&](const char* key, size_t count, std::vector<double>* values) {
    if (!json.contains(key) || !json[key].is_array()) {
      FailNetworkFile(path, name + "." + key + " must be an array of numbers");
    }
    const nlohmann::json& array = json[key];
    if (array.size() != count) {
      FailNetworkFile(path, name + "." + key + " has " + std::to_string(array.size()) +
                                " values, expected " + std::to_string(count));
    }
    values->reserve(count);
    for (size_t k = 0; k < count; ++k) {
      if (!array[k].is_number() || !std::isfinite(array[k].get<double>())) {
        FailNetworkFile(path,
                        name + "." + key + "[" + std::to_string(k) + "] is not a finite number");
      }
      values->push_back(array[k].get<double>());
    }
  };
  read_numbers("weights_row_major_in_by_out", static_cast<size_t>(layer.in) * layer.out,
               &layer.weights);
  read_numbers("bias", layer.out, &layer.bias);
  return layer;
}

// The network's input for one pair (README steps 1-3), or false below the horizon.
// cos/sin of phi_h and theta_h come from h itself: rotating by -phi_h about z maps
// (x, y) -> (x cos + y sin, y cos - x sin); by -theta_h about y maps
// (x, z) -> (x cos - z sin, x sin + z cos).
template <typename T>
inline bool NetworkInput(const Vec3& w_i, const Vec3& w_o, T* x, int stride) {
  if (w_i.z <= 0 || w_o.z <= 0) return false;
  const Vec3 h = Normalize(w_i + w_o);
  const double sin_h = std::sqrt(h.x * h.x + h.y * h.y);
  const double cos_h = h.z;
  double cos_phi = 1.0, sin_phi = 0.0;
  if (sin_h > 0) {
    cos_phi = h.x / sin_h;
    sin_phi = h.y / sin_h;
  }
  const double tx = w_i.x * cos_phi + w_i.y * sin_phi;
  const double ty = w_i.y * cos_phi - w_i.x * sin_phi;
  x[0 * stride] = static_cast<T>(sin_h);
  x[1 * stride] = T(0);
  x[2 * stride] = static_cast<T>(cos_h);
  x[3 * stride] = static_cast<T>(tx * cos_h - w_i.z * sin_h);
  x[4 * stride] = static_cast<T>(ty);
  x[5 * stride] = static_cast<T>(tx * sin_h + w_i.z * cos_h);
  return true;
}

// 32 bytes of T as one GCC vector (spelled per type: GCC ignores vector_size on a dependent type).
template <typename T>
struct Vector32;
template <>
struct Vector32<double> {
  typedef double type __attribute__((vector_size(32)));
};
template <>
struct Vector32<float> {
  typedef float type __attribute__((vector_size(32)));
};

// dst[j][k] = act(b[j] + sum_i w_t[j][i] src[i][k]) for the pairs k < tiles * kWidth, with
// rows `stride` apart and in inputs, summed in the same order (i ascending, from the bias) for
// every kWidth and kOuts, so every version rounds alike. For kWidth a multiple of the lanes of a
// 32-byte vector (4 doubles, 8 floats) the accumulators are GCC vectors kept in registers (two
// SSE2 registers each on any x86-64, one AVX2 register in the AVX2 versions below), for kOuts
// neurons at once: each load of an input row serves kOuts neurons instead of one (the loads,
// not the arithmetic, bounded the one-neuron loop).
template <typename T, int kWidth, int kOuts>
[[gnu::always_inline]] inline void DenseNeurons(int in, const T* w_t, const T* bias, const T* src,
                                                T* dst, int stride, int k0, int j0, bool relu) {
  using Vector = typename Vector32<T>::type;
  static_assert(sizeof(Vector) == 32);
  constexpr int kLanes = 32 / sizeof(T);
  constexpr int kVectors = kWidth / kLanes;
  const T* w[kOuts];
  Vector acc[kOuts][kVectors];
  for (int o = 0; o < kOuts; ++o) {
    w[o] = w_t + static_cast<size_t>(j0 + o) * in;
    for (int q = 0; q < kVectors; ++q) acc[o][q] = Vector{} + bias[j0 + o];
  }
  for (int i = 0; i < in; ++i) {
    const T* row = src + static_cast<size_t>(i) * stride + k0;
    Vector w_i[kOuts];
    for (int o = 0; o < kOuts; ++o) w_i[o] = Vector{} + w[o][i];
    for (int q = 0; q < kVectors; ++q) {
      Vector x;
      std::memcpy(&x, row + kLanes * q, sizeof(x));
      for (int o = 0; o < kOuts; ++o) acc[o][q] += w_i[o] * x;
    }
  }
  for (int o = 0; o < kOuts; ++o) {
    T* out = dst + static_cast<size_t>(j0 + o) * stride + k0;
    for (int q = 0; q < kVectors; ++q) {
      if (relu) acc[o][q] = acc[o][q] > T(0) ? acc[o][q] : Vector{};
      std::memcpy(out + kLanes * q, &acc[o][q], sizeof(Vector));
    }
  }
}

template <typename T, int kWidth>
[[gnu::always_inline]] inline void Dense(int in, int out_count, const T* w_t, const T* bias,
                                         const T* src, T* dst, int stride, int tiles, bool relu) {
  for (int tile = 0; tile < tiles; ++tile) {
    const int k0 = tile * kWidth;
    if constexpr (kWidth % (32 / sizeof(T)) == 0) {
      // Three neurons at a time: 12 accumulators (doubles), an input and three weights fill
      // AVX2's 16 registers.
      int j = 0;
      for (; j + 3 <= out_count; j += 3)
        DenseNeurons<T, kWidth, 3>(in, w_t, bias, src, dst, stride, k0, j, relu);
      for (; j < out_count; ++j)
        DenseNeurons<T, kWidth, 1>(in, w_t, bias, src, dst, stride, k0, j, relu);
    } else {
      for (int j = 0; j < out_count; ++j) {
        const T* w = w_t + static_cast<size_t>(j) * in;
        T* out = dst + static_cast<size_t>(j) * stride + k0;
        for (int k = 0; k < kWidth; ++k) {
          T acc = bias[j];
          const T* col = src + k0 + k;
          for (int i = 0; i < in; ++i) acc += w[i] * col[static_cast<size_t>(i) * stride];
          out[k] = relu ? std::max(acc, T(0)) : acc;
        }
      }
    }
  }
}

template <typename T>
LayerWeights<T> Transposed(const NbrdfNetwork::Layer& layer) {
  LayerWeights<T> t;
  t.in = layer.in;
  t.out = layer.out;
  t.w_t.resize(layer.weights.size());
  for (int i = 0; i < layer.in; ++i) {
    for (int j = 0; j < layer.out; ++j) {
      t.w_t[static_cast<size_t>(j) * layer.in + i] =
          static_cast<T>(layer.weights[static_cast<size_t>(i) * layer.out + j]);
    }
  }
  t.bias.assign(layer.bias.begin(), layer.bias.end());
  return t;
}

// The network's three layers (ReLU, ReLU, linear) on tiles of kWidth pairs, rows `stride` apart.
// channel >= 0: the last layer's neuron of that output only (each output is one neuron there).
template <typename T, int kWidth>
[[gnu::always_inline]] inline void ThreeLayers(const std::array<LayerWeights<T>, 3>& layers,
                                               const T* x, T* a1, T* a2, T* y, int stride,
                                               int tiles, int channel = -1) {
  const auto& [l1, l2, l3] = layers;
  Dense<T, kWidth>(l1.in, l1.out, l1.w_t.data(), l1.bias.data(), x, a1, stride, tiles, true);
  Dense<T, kWidth>(l2.in, l2.out, l2.w_t.data(), l2.bias.data(), a1, a2, stride, tiles, true);
  if (channel >= 0) {
    Dense<T, kWidth>(l3.in, 1, l3.w_t.data() + static_cast<size_t>(channel) * l3.in,
                     l3.bias.data() + channel, a2, y + static_cast<size_t>(channel) * stride,
                     stride, tiles, false);
  } else {
    Dense<T, kWidth>(l3.in, l3.out, l3.w_t.data(), l3.bias.data(), a2, y, stride, tiles, false);
  }
}

// The three layers of a block. Compiled twice, for x86-64 (SSE2) and for AVX2, and the version
// the CPU supports is picked when the program starts (GCC's and Clang's target_clones). Neither
// version contracts to fused multiply-adds, so both round exactly as Eval() does.
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
__attribute__((target_clones("avx2", "default")))
#endif
void EvaluateLayers(const std::array<LayerWeights<double>, 3>& layers, const double* x,
                    double* a1, double* a2, double* y, int count) {
  ThreeLayers<double, kTile>(layers, x, a1, a2, y, kBlock, TilesFor(count, kTile));
}

// NetworkInput of a block's pairs for the single precision layers, into rows kBlock apart, with
// valid[k] false below the horizon (whose inputs are set to 0). Without NetworkInput's branches,
// so that the compiler vectorizes it: h's two square roots and divisions per pair had been a
// tenth of the transport build. The same features up to double rounding (before the cast to
// float): sin and cos of theta_h are |v_xy| / |v| and v_z / |v| of v = w_i + w_o, and phi_h's
// cos and sin v_x / |v_xy| and v_y / |v_xy|.
[[gnu::always_inline]] inline void BlockInputsFloat(const Vec3* w_i, const Vec3* w_o, int count,
                                                    float* x, bool* valid) {
  for (int k = 0; k < count; ++k) {
    const Vec3 a = w_i[k], b = w_o[k];
    const bool ok = a.z > 0 && b.z > 0;
    valid[k] = ok;
    const double vx = a.x + b.x, vy = a.y + b.y, vz = a.z + b.z;
    const double r2 = vx * vx + vy * vy;
    const double inv_len = 1.0 / std::sqrt(r2 + vz * vz);  // |v| > 0 above the horizon
    const double r = std::sqrt(r2);
    const double inv_r = 1.0 / (r2 > 0 ? r : 1.0);
    const double sin_h = r * inv_len, cos_h = vz * inv_len;
    const double cos_phi = r2 > 0 ? vx * inv_r : 1.0, sin_phi = vy * inv_r;
    const double tx = a.x * cos_phi + a.y * sin_phi;
    const double ty = a.y * cos_phi - a.x * sin_phi;
    x[0 * kBlock + k] = ok ? static_cast<float>(sin_h) : 0.0f;
    x[1 * kBlock + k] = 0.0f;
    x[2 * kBlock + k] = ok ? static_cast<float>(cos_h) : 0.0f;
    x[3 * kBlock + k] = ok ? static_cast<float>(tx * cos_h - a.z * sin_h) : 0.0f;
    x[4 * kBlock + k] = ok ? static_cast<float>(ty) : 0.0f;
    x[5 * kBlock + k] = ok ? static_cast<float>(tx * sin_h + a.z * cos_h) : 0.0f;
  }
}

// A block in single precision (EvalBatchSinglePrecision): inputs, then the three layers with 8
// pairs per AVX2 register, and fused multiply-adds where the CPU has them (FMA3; the compiler
// fuses each neuron's acc += w x), on tiles of 32 pairs: half the arithmetic instructions, twice
// the neurons' sums per load of a weight, and each sum rounded once per term instead of twice
// (BM_EvalChannelBatch 37.8 -> 32.2 ns per pair by the fusing, -> ~29 by the wider tiles). Not
// bound to Eval's rounding (the single precision batch is already within float's ~1e-6 of it),
// but the same on every CPU with FMA3; a CPU without it (or a build by GCC, which does not fuse
// in ISO C++ mode) gets the unfused SSE2 or AVX2 version. Both EvalBatchSinglePrecision and
// EvalChannelBatchSinglePrecision come here, so they agree bit for bit on any one machine.
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
__attribute__((target("avx2,fma"))) void EvaluateBlockFloatFma(
    const std::array<LayerWeights<float>, 3>& layers, const Vec3* w_i, const Vec3* w_o, int count,
    float* x, float* a1, float* a2, float* y, bool* valid, int channel) {
  BlockInputsFloat(w_i, w_o, count, x, valid);
  ThreeLayers<float, kFmaFloatTile>(layers, x, a1, a2, y, kBlock, TilesFor(count, kFmaFloatTile),
                                    channel);
}

__attribute__((target_clones("avx2", "default")))
#endif
void EvaluateBlockFloatUnfused(const std::array<LayerWeights<float>, 3>& layers, const Vec3* w_i,
                               const Vec3* w_o, int count, float* x, float* a1, float* a2,
                               float* y, bool* valid, int channel) {
  BlockInputsFloat(w_i, w_o, count, x, valid);
  ThreeLayers<float, kTile>(layers, x, a1, a2, y, kBlock, TilesFor(count, kTile), channel);
}

void EvaluateBlockFloat(const std::array<LayerWeights<float>, 3>& layers, const Vec3* w_i,
                        const Vec3* w_o, int count, float* x, float* a1, float* a2, float* y,
                        bool* valid, int channel) {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  if (CpuHasAvx2Fma()) {
    return EvaluateBlockFloatFma(layers, w_i, w_o, count, x, a1, a2, y, valid, channel);
  }
#endif
  EvaluateBlockFloatUnfused(layers, w_i, w_o, count, x, a1, a2, y, valid, channel);
}

}  // namespace

NbrdfNetwork ReadNbrdfNetwork(const std::string& path) {
  std::ifstream file(path);
  if (!file) FailNetworkFile(path, "cannot open it; check the path and permissions");
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(file);
  } catch (const nlohmann::json::exception& e) {
    FailNetworkFile(path, std::string("not valid JSON (") + e.what() + ")");
  }
  if (!json.is_object() || !json.contains("format") || json["format"] != kNetworkFormat) {
    FailNetworkFile(path, std::string("\"format\" must be \"") + kNetworkFormat +
                              "\" (see data/materials/README.md)");
  }
  if (!json.contains("layers") || !json["layers"].is_array() || json["layers"].size() != 3) {
    FailNetworkFile(path, "\"layers\" must be an array of 3 dense layers");
  }
  NbrdfNetwork network;
  if (json.contains("material") && json["material"].is_string()) {
    network.material = json["material"].get<std::string>();
  }
  for (int k = 0; k < 3; ++k) network.layers[k] = ReadLayer(path, json["layers"][k], k);
  const auto& layers = network.layers;
  if (layers[0].in != kInputs) {
    FailNetworkFile(path,
                    "layers[0].in is " + std::to_string(layers[0].in) + ", expected 6 inputs");
  }
  if (layers[2].out != kOutputs) {
    FailNetworkFile(path,
                    "layers[2].out is " + std::to_string(layers[2].out) + ", expected 3 (RGB)");
  }
  for (int k = 1; k < 3; ++k) {
    if (layers[k].in != layers[k - 1].out) {
      FailNetworkFile(path, "layers[" + std::to_string(k) + "].in is " +
                                std::to_string(layers[k].in) + " but layers[" +
                                std::to_string(k - 1) + "].out is " +
                                std::to_string(layers[k - 1].out));
    }
    if (layers[k].in > kMaxHidden) {
      FailNetworkFile(path, "hidden layer " + std::to_string(k) + " has " +
                                std::to_string(layers[k].in) + " units; at most 256 are supported");
    }
  }
  return network;
}

std::vector<std::string> BundledMaterialNames(const std::string& set) {
  const std::string folder = DataPath("data/materials/" + set);
  std::error_code error;
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(folder, error)) {
    if (entry.path().extension() == ".json") names.push_back(entry.path().stem().string());
  }
  if (error) {
    throw InputError("bundled materials folder " + folder + " cannot be read (" + error.message() +
                     "); set ZBRDF_DATA_DIR to a zbrdf source tree");
  }
  std::sort(names.begin(), names.end());
  return names;
}

NbrdfBrdf::NbrdfBrdf(NbrdfNetwork network, std::string spec)
    : NbrdfBrdf(std::move(network), std::move(spec), nullptr) {}

NbrdfBrdf::NbrdfBrdf(NbrdfNetwork network, std::string spec,
                     std::shared_ptr<const HalfVectorProxySampler> sampler)
    : network_(std::move(network)), spec_(std::move(spec)) {
  // Validates the chain again for networks built in code rather than read from a file.
  const auto& layers = network_.layers;
  ZBRDF_ASSERT(layers[0].in == kInputs && layers[2].out == kOutputs &&
                   layers[1].in == layers[0].out && layers[2].in == layers[1].out &&
                   layers[1].in <= kMaxHidden && layers[2].in <= kMaxHidden,
               "NbrdfBrdf: layer sizes must chain 6 -> hidden (<= 256) -> hidden -> 3");
  for (int k = 0; k < 3; ++k) {
    ZBRDF_ASSERT(layers[k].weights.size() == static_cast<size_t>(layers[k].in) * layers[k].out &&
                     layers[k].bias.size() == static_cast<size_t>(layers[k].out),
                 "NbrdfBrdf: weight or bias count does not match the layer size");
    weights_[k] = Transposed<double>(layers[k]);
    weights_float_[k] = Transposed<float>(layers[k]);
  }
  if (sampler) {
    sampler_ = std::move(sampler);
  } else {
    FitProxySampler();
  }
}

namespace {

// Bundled materials already read by this process, by resolved path, with their fitted proxy
// samplers: the files are read-only data, so a second FromName of a material (a test suite, a
// batch, the fuzz target of material specs) costs a copy of its weights instead of parsing the
// file and the sampler's ~16000 network evaluations. At most the bundled sets' 118 entries of a
// few tens of kB.
struct BundledNetwork {
  NbrdfNetwork network;
  std::shared_ptr<const HalfVectorProxySampler> sampler;
};
std::mutex bundled_mutex;
std::map<std::string, std::shared_ptr<const BundledNetwork>>& Bundled() {
  static std::map<std::string, std::shared_ptr<const BundledNetwork>> bundled;
  return bundled;
}

}  // namespace

std::unique_ptr<NbrdfBrdf> NbrdfBrdf::FromName(const std::string& name, const std::string& set) {
  const std::string folder = "data/materials/" + set;
  const std::string spec = set + ":" + name;
  // Only names found among the bundled files below enter the cache, so a hit needs no listing.
  const std::string path = DataPath(folder + "/" + name + ".json");
  {
    std::lock_guard<std::mutex> lock(bundled_mutex);
    const auto it = Bundled().find(path);
    if (it != Bundled().end()) {
      return std::unique_ptr<NbrdfBrdf>(new NbrdfBrdf(it->second->network, spec, it->second->sampler));
    }
  }
  const std::vector<std::string> names = BundledMaterialNames(set);
  if (!std::binary_search(names.begin(), names.end(), name)) {
    const std::vector<std::string> close = ClosestNames(name, names);
    std::string message = "unknown measured material '" + name + "'";
    for (size_t k = 0; k < close.size(); ++k) {
      message += (k == 0 ? "; did you mean '" : " or '") + close[k] + "'";
    }
    message += (close.empty() ? "; the " : "? The ") + std::to_string(names.size()) +
               " bundled materials are the NAME.json files in " + DataPath(folder) + "; use " +
               set + ":NAME with one of those names";
    throw InputError(message);
  }
  auto brdf = std::make_unique<NbrdfBrdf>(ReadNbrdfNetwork(path), spec);
  std::lock_guard<std::mutex> lock(bundled_mutex);
  Bundled().emplace(path, std::make_shared<const BundledNetwork>(
                              BundledNetwork{brdf->network_, brdf->sampler_}));
  return brdf;
}

std::unique_ptr<NbrdfBrdf> NbrdfBrdf::FromFile(const std::string& path) {
  return std::make_unique<NbrdfBrdf>(ReadNbrdfNetwork(path), "file:" + path);
}

namespace {
// f = max(exp(y) - 1, 0): the network's output map.
inline double OutputMap(double y) { return std::max(std::exp(y) - 1.0, 0.0); }
// The colour of pair k of a block's outputs y (row c: channel c).
template <typename T>
Rgb OutputRgb(const T* y, int k) {
  static_assert(kOutputs == 3, "a colour per pair");
  return {OutputMap(static_cast<double>(y[k])), OutputMap(static_cast<double>(y[kBlock + k])),
          OutputMap(static_cast<double>(y[2 * kBlock + k]))};
}
}  // namespace

template <typename T>
const T* NbrdfBrdf::EvalBlock(const Vec3* w_i, const Vec3* w_o, int count, T* scratch, bool* valid,
                              int channel) const {
  // Structure-of-arrays scratch: each row holds one feature for the kBlock pairs. Rows past
  // `count` and of pairs below the horizon hold stale finite values; their results are dropped.
  const int hidden1 = network_.layers[0].out, hidden2 = network_.layers[1].out;
  T* x = scratch;
  T* a1 = x + kInputs * kBlock;
  T* a2 = a1 + hidden1 * kBlock;
  T* y = a2 + hidden2 * kBlock;
  if constexpr (std::is_same_v<T, float>) {
    EvaluateBlockFloat(weights_float_, w_i, w_o, count, x, a1, a2, y, valid, channel);
  } else {
    ZBRDF_ASSERT(channel < 0, "EvalBlock: one channel is single precision's only");
    for (int k = 0; k < count; ++k) valid[k] = NetworkInput(w_i[k], w_o[k], x + k, kBlock);
    EvaluateLayers(weights_, x, a1, a2, y, count);
  }
  return y;
}

Rgb NbrdfBrdf::Eval(const Vec3& w_i, const Vec3& w_o) const {
  double x[kInputs];
  if (!NetworkInput(w_i, w_o, x, 1)) return {};
  double a1[kMaxHidden], a2[kMaxHidden], y[kOutputs];
  ThreeLayers<double, 1>(weights_, x, a1, a2, y, 1, 1);
  return {OutputMap(y[0]), OutputMap(y[1]), OutputMap(y[2])};
}

template <typename T, typename Out>
void NbrdfBrdf::EvalBatchIn(std::span<const Vec3> w_i, std::span<const Vec3> w_o, const Out& out,
                            int channel) const {
  ZBRDF_ASSERT(w_i.size() == w_o.size(), "EvalBatch size mismatch");
  const size_t rows = kInputs + network_.layers[0].out + network_.layers[1].out + kOutputs;
  std::vector<T> scratch(rows * kBlock, T(0));
  bool valid[kBlock];
  for (size_t start = 0; start < w_i.size(); start += kBlock) {
    const int count = static_cast<int>(std::min<size_t>(kBlock, w_i.size() - start));
    const T* y = EvalBlock(&w_i[start], &w_o[start], count, scratch.data(), valid, channel);
    out(start, count, y, valid);
  }
}

namespace {

// EvalBatchIn's output for whole colours.
template <typename T>
auto RgbOutput(std::span<Rgb> f) {
  return [f](size_t start, int count, const T* y, const bool* valid) {
    for (int k = 0; k < count; ++k) f[start + k] = valid[k] ? OutputRgb(y, k) : Rgb();
  };
}

}  // namespace

void NbrdfBrdf::EvalBatch(std::span<const Vec3> w_i, std::span<const Vec3> w_o,
                          std::span<Rgb> f) const {
  ZBRDF_ASSERT(w_i.size() == f.size(), "EvalBatch size mismatch");
  EvalBatchIn<double>(w_i, w_o, RgbOutput<double>(f));
}

void NbrdfBrdf::EvalBatchSinglePrecision(std::span<const Vec3> w_i, std::span<const Vec3> w_o,
                                         std::span<Rgb> f) const {
  ZBRDF_ASSERT(w_i.size() == f.size(), "EvalBatch size mismatch");
  EvalBatchIn<float>(w_i, w_o, RgbOutput<float>(f));
}

void NbrdfBrdf::EvalChannelBatchSinglePrecision(std::span<const Vec3> w_i,
                                                std::span<const Vec3> w_o, int channel,
                                                std::span<double> value) const {
  ZBRDF_ASSERT(w_i.size() == value.size() && channel >= -1 && channel < kOutputs,
               "EvalChannelBatchSinglePrecision: size mismatch or channel outside -1..2");
  if (channel < 0) {
    EvalBatchIn<float>(w_i, w_o, [&](size_t start, int count, const float* y, const bool* valid) {
      for (int k = 0; k < count; ++k)
        value[start + k] = valid[k] ? OutputRgb(y, k).Luminance() : 0.0;
    });
    return;
  }
  // Only the channel's output neuron (the last layer is a seventh of the network's work).
  EvalBatchIn<float>(
      w_i, w_o,
      [&](size_t start, int count, const float* y, const bool* valid) {
        const float* row = y + channel * kBlock;
        for (int k = 0; k < count; ++k) value[start + k] = valid[k] ? OutputMap(row[k]) : 0.0;
      },
      channel);
}

}  // namespace zbrdf
