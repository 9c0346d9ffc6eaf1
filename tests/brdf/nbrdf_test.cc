#include "brdf/nbrdf.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "basis/data_path.h"
#include "basis/error.h"
#include "brdf/material_spec.h"
#include "brdf_checks.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

struct ReferenceRow {
  const char* material;
  double theta_i, phi_i, theta_o, phi_o;
  double f[3];
};

// data/materials/README.md, "Reference values".
constexpr ReferenceRow kReference[] = {
    {"blue-acrylic", 0.30, 0.00, 0.30, 3.14159265, {16.4897, 14.0144, 14.171}},
    {"blue-acrylic", 0.70, 1.00, 0.20, 2.50000000, {0.003832, 0.01148, 0.034085}},
    {"blue-acrylic", 1.20, 0.30, 1.10, 3.60000000, {0.007676, 0.016356, 0.039548}},
    {"blue-acrylic", 0.05, 0.00, 0.05, 3.14159265, {15.9479, 13.1431, 13.1751}},
    {"gold-metallic-paint", 0.30, 0.00, 0.30, 3.14159265, {0.478704, 0.35341, 0.117704}},
    {"gold-metallic-paint", 0.70, 1.00, 0.20, 2.50000000, {0.032924, 0.02352, 0.009067}},
    {"gold-metallic-paint", 1.20, 0.30, 1.10, 3.60000000, {0.673566, 0.422502, 0.175591}},
    {"gold-metallic-paint", 0.05, 0.00, 0.05, 3.14159265, {0.456665, 0.344078, 0.125688}},
    {"red-fabric", 0.30, 0.00, 0.30, 3.14159265, {0.079652, 0.012935, 0.007482}},
    {"red-fabric", 0.70, 1.00, 0.20, 2.50000000, {0.070162, 0.010199, 0.004318}},
    {"red-fabric", 1.20, 0.30, 1.10, 3.60000000, {0.1425, 0.037191, 0.028162}},
    {"red-fabric", 0.05, 0.00, 0.05, 3.14159265, {0.087127, 0.014687, 0.00929}},
    {"chrome", 0.30, 0.00, 0.30, 3.14159265, {503.688, 528.952, 523.949}},
    {"chrome", 0.70, 1.00, 0.20, 2.50000000, {0.001058, 0.000939, 0.001038}},
    {"chrome", 1.20, 0.30, 1.10, 3.60000000, {0.010395, 0.009669, 0.010177}},
    {"chrome", 0.05, 0.00, 0.05, 3.14159265, {461.144, 483.792, 479.987}},
};

// The README prints six significant digits, fewer for some entries (0.003832, 0.1425): the
// tolerance is 1e-4 relative or half a unit in the last printed digit, whichever is larger.
double PrintedTolerance(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.6g", value);
  const std::string digits(text);
  const size_t dot = digits.find('.');
  const int decimals = dot == std::string::npos ? 0 : static_cast<int>(digits.size() - dot - 1);
  return std::max(1e-4 * std::abs(value), 0.5 * std::pow(10.0, -decimals));
}

TEST(NbrdfTest, MatchesTheReadmeReferenceTable) {
  for (const ReferenceRow& row : kReference) {
    const auto brdf = NbrdfBrdf::FromName(row.material);
    const Rgb f = brdf->Eval(SphericalDirection(row.theta_i, row.phi_i),
                             SphericalDirection(row.theta_o, row.phi_o));
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(f[c], row.f[c], PrintedTolerance(row.f[c]))
          << row.material << " theta_i=" << row.theta_i << " channel " << c;
    }
  }
}

// The README's recipe, written out directly: trigonometric angles, Rodrigues rotations and
// row-major matrix products.
Rgb ReadmeRecipe(const NbrdfNetwork& network, const Vec3& w_i, const Vec3& w_o) {
  if (w_i.z <= 0 || w_o.z <= 0) return {};
  const auto rotate = [](const Vec3& v, const Vec3& a, double t) {
    return v * std::cos(t) + a * (Dot(a, v) * (1 - std::cos(t))) + Cross(a, v) * std::sin(t);
  };
  const Vec3 h = Normalize(w_i + w_o);
  const double theta_h = std::acos(h.z), phi_h = std::atan2(h.y, h.x);
  const Vec3 d = rotate(rotate(w_i, {0, 0, 1}, -phi_h), {0, 1, 0}, -theta_h);
  std::vector<double> x = {std::sin(theta_h), 0, std::cos(theta_h), d.x, d.y, d.z};
  for (int l = 0; l < 3; ++l) {
    const NbrdfNetwork::Layer& layer = network.layers[l];
    std::vector<double> y(layer.bias);
    for (int i = 0; i < layer.in; ++i) {
      for (int j = 0; j < layer.out; ++j) y[j] += x[i] * layer.weights[i * layer.out + j];
    }
    if (l < 2) {
      for (double& v : y) v = std::max(v, 0.0);
    }
    x = y;
  }
  return {std::max(std::exp(x[0]) - 1, 0.0), std::max(std::exp(x[1]) - 1, 0.0),
          std::max(std::exp(x[2]) - 1, 0.0)};
}

TEST(NbrdfTest, EvalAndEvalBatchFollowTheRecipe) {
  testing::Rng rng(101);
  for (const char* name : {"blue-acrylic", "chrome", "aventurnine"}) {
    const auto brdf = NbrdfBrdf::FromName(name);
    // 1000 pairs (not a multiple of the batch block), a tenth of them below the horizon.
    std::vector<Vec3> w_i(1000), w_o(1000);
    for (size_t k = 0; k < w_i.size(); ++k) {
      w_i[k] = testing::RandomUpperDirection(rng);
      w_o[k] = testing::RandomUpperDirection(rng);
      if (k % 10 == 7) w_i[k].z = -w_i[k].z;
    }
    std::vector<Rgb> batch(w_i.size());
    brdf->EvalBatch(w_i, w_o, batch);
    for (size_t k = 0; k < w_i.size(); ++k) {
      const Rgb expected = ReadmeRecipe(brdf->network(), w_i[k], w_o[k]);
      const Rgb single = brdf->Eval(w_i[k], w_o[k]);
      for (int c = 0; c < 3; ++c) {
        // Same arithmetic up to the trigonometry-free rotations: rounding only.
        ASSERT_NEAR(single[c], expected[c], 1e-11 * (1 + expected[c])) << name << " " << k;
        ASSERT_NEAR(batch[k][c], single[c], 1e-13 * (1 + single[c])) << name << " " << k;
      }
    }
  }
}

TEST(NbrdfTest, SinglePrecisionBatchIsEvalBatchToFloatRounding) {
  testing::Rng rng(102);
  for (const char* name : {"blue-acrylic", "chrome", "black-obsidian", "white-paint"}) {
    const auto brdf = NbrdfBrdf::FromName(name);
    std::vector<Vec3> w_i(5000), w_o(5000);
    for (size_t k = 0; k < w_i.size(); ++k) {
      w_i[k] = testing::RandomUpperDirection(rng);
      w_o[k] = testing::RandomUpperDirection(rng);
      if (k % 10 == 7) w_i[k].z = -w_i[k].z;
    }
    std::vector<Rgb> f64(w_i.size()), f32(w_i.size());
    brdf->EvalBatch(w_i, w_o, f64);
    brdf->EvalBatchSinglePrecision(w_i, w_o, f32);
    double max_y_error = 0;
    for (size_t k = 0; k < w_i.size(); ++k) {
      for (int c = 0; c < 3; ++c) {
        if (w_i[k].z <= 0) {
          ASSERT_EQ(f32[k][c], 0.0) << name << " " << k;
          continue;
        }
        // f = exp(y) - 1, so |df| / (1 + f) is the error of the network's output y: float's
        // 6e-8 rounding over three layers of 6-21 terms of magnitude ~1 is ~1e-6 (measured:
        // at most 1.4e-6 over 200000 pairs of merl:blue-acrylic, 2.3e-6 for rgl:cardboard);
        // 1e-5 leaves room and is still far below the simulator's 5e-3 Monte Carlo error. A
        // wrong lane or layer gives errors of order 1e-2 to 1.
        max_y_error = std::max(max_y_error, std::abs(f32[k][c] - f64[k][c]) / (1 + f64[k][c]));
      }
    }
    EXPECT_LT(max_y_error, 1e-5) << name;
  }
}

// EvalChannelBatchSinglePrecision is one channel (or the luminance) of
// EvalBatchSinglePrecision, bit for bit: the network's override (which maps only the asked
// channel's output) and the default of every other model, over more pairs than one block or
// chunk, with pairs below the horizon.
TEST(NbrdfTest, OneChannelIsThatChannelOfTheSinglePrecisionBatch) {
  testing::Rng rng(103);
  const auto network = NbrdfBrdf::FromName("blue-acrylic");
  const auto ggx = MakeBrdf("ggx:alpha=0.2,F0=0.04,kd=0.3");
  for (const Brdf* brdf : std::vector<const Brdf*>{network.get(), ggx.get()}) {
    std::vector<Vec3> w_i(300), w_o(300);
    for (size_t k = 0; k < w_i.size(); ++k) {
      w_i[k] = testing::RandomUpperDirection(rng);
      w_o[k] = testing::RandomUpperDirection(rng);
      if (k % 10 == 7) w_i[k].z = -w_i[k].z;
    }
    std::vector<Rgb> f(w_i.size());
    brdf->EvalBatchSinglePrecision(w_i, w_o, f);
    for (int channel = -1; channel < 3; ++channel) {
      std::vector<double> value(w_i.size(), -1.0);
      brdf->EvalChannelBatchSinglePrecision(w_i, w_o, channel, value);
      for (size_t k = 0; k < w_i.size(); ++k) {
        ASSERT_EQ(value[k], channel < 0 ? f[k].Luminance() : f[k][channel])
            << brdf->Spec() << " channel " << channel << " pair " << k;
      }
    }
  }
}

TEST(NbrdfTest, BundledNamesAndErrors) {
  const std::vector<std::string> names = BundledMaterialNames();
  EXPECT_EQ(names.size(), 100u);
  EXPECT_TRUE(std::is_sorted(names.begin(), names.end()));
  EXPECT_TRUE(std::binary_search(names.begin(), names.end(), "blue-acrylic"));
  try {
    NbrdfBrdf::FromName("blue-acrylc");
    ADD_FAILURE() << "an unknown name was accepted";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("unknown measured material 'blue-acrylc'"), std::string::npos);
    EXPECT_NE(message.find("did you mean 'blue-acrylic'"), std::string::npos) << message;
    EXPECT_NE(message.find(DataPath("data/materials/merl")), std::string::npos) << message;
  }
  EXPECT_THROW(NbrdfBrdf::FromName("../merl/chrome"), InputError);
  const auto brdf = NbrdfBrdf::FromName("red-fabric");
  EXPECT_EQ(brdf->Spec(), "merl:red-fabric");
  EXPECT_FALSE(brdf->IsReciprocal());
  EXPECT_FALSE(brdf->IsEnergyConserving());
}

// A bundled material is read once per process: later FromName calls share the fitted sampler
// and are the same function as a network read from the file directly.
TEST(NbrdfTest, BundledMaterialsAreReadOncePerProcess) {
  const auto first = NbrdfBrdf::FromName("gold-metallic-paint2");
  const auto second = NbrdfBrdf::FromName("gold-metallic-paint2");
  EXPECT_EQ(&first->sampler(), &second->sampler());
  EXPECT_EQ(second->Spec(), "merl:gold-metallic-paint2");
  const auto from_file =
      NbrdfBrdf::FromFile(DataPath("data/materials/merl/gold-metallic-paint2.json"));
  EXPECT_NE(&from_file->sampler(), &first->sampler());  // files are not cached: they may change
  testing::Rng rng(7);
  for (int k = 0; k < 50; ++k) {
    const Vec3 w_i = testing::RandomUpperDirection(rng), w_o = testing::RandomUpperDirection(rng);
    const Rgb a = second->Eval(w_i, w_o), b = from_file->Eval(w_i, w_o);
    EXPECT_EQ(a.r, b.r);
    EXPECT_EQ(a.b, b.b);
    EXPECT_EQ(second->Pdf(w_o, w_i), from_file->Pdf(w_o, w_i));
  }
  // The same name in the other set is another file, and unknown names are still refused.
  EXPECT_THROW(NbrdfBrdf::FromName("gold-metallic-paint2", "rgl"), InputError);
  EXPECT_THROW(NbrdfBrdf::FromName("gold-metallic-paint9"), InputError);
}

// Writes text to a per-process temp file and returns ReadNbrdfNetwork's error ("" if none).
std::string NetworkError(const std::string& text) {
  const std::string path =
      (std::filesystem::temp_directory_path() / (std::to_string(getpid()) + "_zbrdf_network.json"))
          .string();
  std::ofstream(path) << text;
  std::string message;
  try {
    ReadNbrdfNetwork(path);
  } catch (const InputError& e) {
    message = e.what();
  }
  std::filesystem::remove(path);
  if (!message.empty()) {
    EXPECT_NE(message.find(path), std::string::npos) << message;
  }
  return message;
}

std::string Layer(int in, int out, int weights, int biases) {
  std::string text = "{\"in\": " + std::to_string(in) + ", \"out\": " + std::to_string(out) +
                     ", \"weights_row_major_in_by_out\": [";
  for (int k = 0; k < weights; ++k) text += (k ? ", " : "") + std::string("0.1");
  text += "], \"bias\": [";
  for (int k = 0; k < biases; ++k) text += (k ? ", " : "") + std::string("0");
  return text + "]}";
}

TEST(NbrdfTest, MalformedNetworkFilesNameTheFieldAtFault) {
  const std::string good = "{\"format\": \"nbrdf-mlp-v1\", \"layers\": [" + Layer(6, 4, 24, 4) +
                           ", " + Layer(4, 4, 16, 4) + ", " + Layer(4, 3, 12, 3) + "]}";
  EXPECT_EQ(NetworkError(good), "");
  EXPECT_NE(NetworkError("{\"format\": ").find("not valid JSON"), std::string::npos);
  EXPECT_NE(NetworkError("{\"format\": \"other\", \"layers\": []}").find("\"format\""),
            std::string::npos);
  EXPECT_NE(NetworkError("{\"format\": \"nbrdf-mlp-v1\", \"layers\": [" + Layer(6, 4, 24, 4) + "]}")
                .find("array of 3 dense layers"),
            std::string::npos);
  EXPECT_NE(NetworkError("{\"format\": \"nbrdf-mlp-v1\", \"layers\": [" + Layer(6, 4, 23, 4) +
                         ", " + Layer(4, 4, 16, 4) + ", " + Layer(4, 3, 12, 3) + "]}")
                .find("layers[0].weights_row_major_in_by_out has 23 values, expected 24"),
            std::string::npos);
  EXPECT_NE(NetworkError("{\"format\": \"nbrdf-mlp-v1\", \"layers\": [" + Layer(6, 4, 24, 4) +
                         ", " + Layer(5, 4, 20, 4) + ", " + Layer(4, 3, 12, 3) + "]}")
                .find("layers[1].in is 5 but layers[0].out is 4"),
            std::string::npos);
  EXPECT_NE(NetworkError("{\"format\": \"nbrdf-mlp-v1\", \"layers\": [" + Layer(5, 4, 20, 4) +
                         ", " + Layer(4, 4, 16, 4) + ", " + Layer(4, 3, 12, 3) + "]}")
                .find("expected 6 inputs"),
            std::string::npos);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
