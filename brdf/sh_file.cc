#include "brdf/sh_file.h"

#include <cmath>
#include <cstdio>

#include <ImfChannelList.h>
#include <ImfDoubleAttribute.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputPart.h>
#include <ImfIntAttribute.h>
#include <ImfMultiPartInputFile.h>
#include <ImfStringAttribute.h>

#include "basis/error.h"
#include "basis/parallel.h"
#include "brdf/exr_header.h"
#include "brdf/exr_writer.h"

namespace zbrdf {
namespace {

constexpr char kShFormat[] = "zbrdf-sh-v1";
constexpr char kQuantity[] = "f_r*cos(theta_i)";
constexpr char kNormalization[] =
    "real spherical harmonics, orthonormal on the unit sphere, Condon-Shortley phase: "
    "Y_l0 = K_l0 P_l(cos theta), Y_lm = sqrt(2) K_lm P_l^m(cos theta) cos(m phi) (m > 0), "
    "Y_lm = sqrt(2) K_l|m| P_l^|m|(cos theta) sin(|m| phi) (m < 0), "
    "K_lm = sqrt((2l+1)/(4 pi) (l-m)!/(l+m)!), P_l^m with the (-1)^m phase; sh-even/sh-odd: "
    "the Y_lm with l+|m| even/odd, same normalization; hsh: H_lm(theta, phi) = sqrt(2) "
    "Y_lm(arccos(2 cos theta - 1), phi) on the upper hemisphere, 0 below";

}  // namespace

int ShBrdfData::size() const { return TargetBasis(target, order).size(); }

Vec3 ShBrdfData::ExitantDirection(int i, int j) const {
  return SphericalDirection((i + 0.5) * 0.5 * M_PI / exitant_theta,
                            (j + 0.5) * 2.0 * M_PI / exitant_phi);
}

void ShBrdfData::FillExitantTables() {
  const TargetBasis basis(target, order);
  const int n = basis.size();
  const int cells = exitant_theta * exitant_phi;
  for (int ch = 0; ch < 3; ++ch) exitant[ch].assign(static_cast<size_t>(cells) * n, 0.0f);
  ParallelFor(cells, 64, [&](int64_t c0, int64_t c1) {
    Eigen::VectorXd t(n);
    for (int64_t c = c0; c < c1; ++c) {
      basis.Eval(ExitantDirection(static_cast<int>(c / exitant_phi), static_cast<int>(c % exitant_phi)),
                 t.data());
      for (int ch = 0; ch < 3; ++ch) {
        const Eigen::VectorXd y = coefficients[ch] * t;
        for (int a = 0; a < n; ++a) exitant[ch][static_cast<size_t>(c) * n + a] = static_cast<float>(y[a]);
      }
    }
  });
}

std::string ShBrdfData::Problems() const {
  if (order < 0 || order > 30) return "SH data: order " + std::to_string(order) + " is out of range [0, 30]";
  if (!(theta_min_rad >= 0 && theta_min_rad < theta_max_rad && theta_max_rad <= 0.5 * M_PI + 1e-12)) {
    return "SH data: the zone is not a valid theta range within [0, 90] deg";
  }
  if (exitant_theta < 1 || exitant_phi < 1) return "SH data: the exitant grid must have >= 1 cell";
  const int n = size();
  for (int ch = 0; ch < 3; ++ch) {
    if (coefficients[ch].rows() != n || coefficients[ch].cols() != n) {
      return std::string("SH data: channel ") + kRgbChannelNames[ch] + " coefficients are not " +
             std::to_string(n) + " x " + std::to_string(n);
    }
    if (!coefficients[ch].allFinite()) {
      return std::string("SH data: channel ") + kRgbChannelNames[ch] +
             " has a non-finite coefficient";
    }
    if (exitant[ch].size() != static_cast<size_t>(exitant_theta) * exitant_phi * n) {
      return std::string("SH data: channel ") + kRgbChannelNames[ch] +
             " per-exitant table has the wrong size (call FillExitantTables())";
    }
  }
  return "";
}

std::string ShLayerName(TargetKind target, int l, int m) {
  char name[32];
  std::snprintf(name, sizeof(name), "%c%d_%d", target == TargetKind::kHsh ? 'H' : 'Y', l, m);
  return name;
}

void WriteShFile(const std::string& path, const ShBrdfData& data) {
  if (const std::string problems = data.Problems(); !problems.empty()) {
    throw InputError("cannot write " + path + ": " + problems);
  }
  const TargetBasis basis(data.target, data.order);
  const int n = basis.size();
  TwoPartExrWriter writer("exitant", data.exitant_phi, data.exitant_theta, "tensor", n);
  writer.SetString("zbrdf.format", kShFormat);
  writer.SetString("zbrdf.target", TargetName(data.target));
  writer.SetInt("zbrdf.order", data.order);
  writer.SetDouble("zbrdf.theta_min_rad", data.theta_min_rad);
  writer.SetDouble("zbrdf.theta_max_rad", data.theta_max_rad);
  writer.SetString("zbrdf.quantity", kQuantity);
  writer.SetString("zbrdf.normalization", kNormalization);
  writer.SetString("zbrdf.info", data.info.dump());
  // Per-exitant layers: one FLOAT image per (function, channel), strided views of `exitant`.
  for (int a = 0; a < n; ++a) {
    const std::string layer = ShLayerName(data.target, basis.degree(a), basis.azimuthal_order(a));
    for (int ch = 0; ch < 3; ++ch) {
      writer.AddImageChannel(layer + "." + kRgbChannelNames[ch], data.exitant[ch].data() + a, n,
                             static_cast<size_t>(n) * data.exitant_phi);
    }
  }
  for (int ch = 0; ch < 3; ++ch) {
    std::vector<float> tensor(static_cast<size_t>(n) * n);
    for (int a = 0; a < n; ++a) {
      for (int b = 0; b < n; ++b) {
        tensor[static_cast<size_t>(a) * n + b] = static_cast<float>(data.coefficients[ch](a, b));
      }
    }
    writer.AddTensorChannel(std::string("y.") + kRgbChannelNames[ch], std::move(tensor));
  }
  writer.Write(path, "SH file " + path);
}

ShBrdfData ReadShFile(const std::string& path) {
  ShBrdfData data;
  CheckExrHeaderSizes(path, path);
  try {
    Imf::MultiPartInputFile file(path.c_str());
    int exitant_part = -1, tensor_part = -1;
    for (int i = 0; i < file.parts(); ++i) {
      if (!file.header(i).hasName()) continue;
      if (file.header(i).name() == "exitant") exitant_part = i;
      if (file.header(i).name() == "tensor") tensor_part = i;
    }
    if (exitant_part < 0 || tensor_part < 0) {
      throw InputError(path + " is not a zbrdf SH file (no 'exitant' and 'tensor' parts)");
    }
    const Imf::Header& h = file.header(tensor_part);
    const auto* format = h.findTypedAttribute<Imf::StringAttribute>("zbrdf.format");
    if (!format || format->value() != kShFormat) {
      throw InputError(path + " is not a zbrdf SH file (zbrdf.format is not " +
                       std::string(kShFormat) + ")");
    }
    auto get_double = [&](const char* name) {
      const auto* a = h.findTypedAttribute<Imf::DoubleAttribute>(name);
      if (!a) throw InputError(path + ": header attribute " + name + " is missing");
      return a->value();
    };
    const auto* target = h.findTypedAttribute<Imf::StringAttribute>("zbrdf.target");
    const auto* order = h.findTypedAttribute<Imf::IntAttribute>("zbrdf.order");
    if (!target || !order) throw InputError(path + ": zbrdf.target or zbrdf.order is missing");
    try {
      data.target = ParseTargetName(target->value());
    } catch (const InputError& e) {
      throw InputError(path + ": zbrdf.target: " + e.what());
    }
    if (order->value() < 0 || order->value() > 30) {
      throw InputError(path + ": zbrdf.order " + std::to_string(order->value()) + " is out of range");
    }
    data.order = order->value();
    data.theta_min_rad = get_double("zbrdf.theta_min_rad");
    data.theta_max_rad = get_double("zbrdf.theta_max_rad");
    if (const auto* info = h.findTypedAttribute<Imf::StringAttribute>("zbrdf.info")) {
      data.info = nlohmann::json::parse(info->value(), nullptr, false);
      if (data.info.is_discarded()) throw InputError(path + ": zbrdf.info is not valid JSON");
    }
    const TargetBasis basis(data.target, data.order);
    const int n = basis.size();
    auto require = [&](const Imf::Header& header, const std::string& name) {
      if (!header.channels().findChannel(name)) throw InputError(path + ": channel " + name + " is missing");
    };
    // Tensor.
    const Imath::Box2i tw = h.dataWindow();
    RequireWindowAtOrigin(tw.min.x, tw.min.y, tw.max.x, tw.max.y, path, "tensor");
    if (tw.max.x - tw.min.x + 1 != n || tw.max.y - tw.min.y + 1 != n) {
      throw InputError(path + ": the tensor part is not " + std::to_string(n) + " x " +
                       std::to_string(n) + " for " + target->value() + " order " +
                       std::to_string(data.order));
    }
    std::array<std::vector<float>, 3> tensor;
    Imf::FrameBuffer tfb;
    for (int ch = 0; ch < 3; ++ch) {
      const std::string name = std::string("y.") + kRgbChannelNames[ch];
      require(h, name);
      tensor[ch].resize(static_cast<size_t>(n) * n);
      char* base = reinterpret_cast<char*>(tensor[ch].data()) -
                   (static_cast<ptrdiff_t>(tw.min.y) * n + tw.min.x) * sizeof(float);
      tfb.insert(name, Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * n));
    }
    Imf::InputPart tpart(file, tensor_part);
    tpart.setFrameBuffer(tfb);
    tpart.readPixels(tw.min.y, tw.max.y);
    for (int ch = 0; ch < 3; ++ch) {
      data.coefficients[ch].resize(n, n);
      for (int a = 0; a < n; ++a) {
        for (int b = 0; b < n; ++b) data.coefficients[ch](a, b) = tensor[ch][static_cast<size_t>(a) * n + b];
      }
    }
    // Per-exitant tables.
    const Imf::Header& eh = file.header(exitant_part);
    const Imath::Box2i ew = eh.dataWindow();
    RequireWindowAtOrigin(ew.min.x, ew.min.y, ew.max.x, ew.max.y, path, "exitant");
    data.exitant_phi = ew.max.x - ew.min.x + 1;
    data.exitant_theta = ew.max.y - ew.min.y + 1;
    const int width = data.exitant_phi;
    Imf::FrameBuffer efb;
    for (int ch = 0; ch < 3; ++ch) {
      data.exitant[ch].assign(static_cast<size_t>(data.exitant_theta) * width * n, 0.0f);
    }
    for (int a = 0; a < n; ++a) {
      const std::string layer = ShLayerName(data.target, basis.degree(a), basis.azimuthal_order(a));
      for (int ch = 0; ch < 3; ++ch) {
        const std::string name = layer + "." + kRgbChannelNames[ch];
        require(eh, name);
        char* base = reinterpret_cast<char*>(data.exitant[ch].data() + a) -
                     (static_cast<ptrdiff_t>(ew.min.y) * width + ew.min.x) *
                         static_cast<ptrdiff_t>(sizeof(float)) * n;
        efb.insert(name, Imf::Slice(Imf::FLOAT, base, sizeof(float) * n, sizeof(float) * n * width));
      }
    }
    Imf::InputPart epart(file, exitant_part);
    epart.setFrameBuffer(efb);
    epart.readPixels(ew.min.y, ew.max.y);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError("cannot read SH file " + path + ": " + e.what());
  }
  if (const std::string problems = data.Problems(); !problems.empty()) {
    throw InputError(path + ": " + problems);
  }
  for (int ch = 0; ch < 3; ++ch) {
    for (float v : data.exitant[ch]) {
      if (!std::isfinite(v)) throw InputError(path + ": a per-exitant coefficient is not finite");
    }
  }
  return data;
}

}  // namespace zbrdf
