#include "acquisition/zonal.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputPart.h>
#include <ImfIntAttribute.h>
#include <ImfMultiPartInputFile.h>
#include <ImfStringAttribute.h>
#include <ImfDoubleAttribute.h>
#include <Iex.h>

#include "basis/error.h"
#include "basis/parallel.h"
#include "basis/quadrature.h"
#include "basis/spherical_harmonics.h"
#include "brdf/exr_header.h"
#include "brdf/exr_writer.h"
#include "rig/direction_maps.h"

namespace zbrdf {

double ExitantGrid::CellSolidAngle(int i) const {
  return phi_step_rad * (std::cos(ThetaLow(i)) - std::cos(ThetaHigh(i)));
}

Vec3 ExitantGrid::CellCenter(int i, int j) const {
  const double cos_mid = 0.5 * (std::cos(ThetaLow(i)) + std::cos(ThetaHigh(i)));
  const double sin_mid = std::sqrt(std::max(0.0, 1 - cos_mid * cos_mid));
  const double phi = (j + 0.5) * phi_step_rad;
  return {sin_mid * std::cos(phi), sin_mid * std::sin(phi), cos_mid};
}

int ExitantGrid::CellOf(const Vec3& w) const {
  const double theta = SphericalTheta(w);
  if (theta < theta_min_rad || theta > theta_max_rad) return -1;
  const int i = std::min(static_cast<int>((theta - theta_min_rad) / theta_step_rad), n_theta - 1);
  const int j = std::min(static_cast<int>(SphericalPhi(w) / phi_step_rad), n_phi - 1);
  return i * n_phi + j;
}

ExitantGrid MakeExitantGrid(const Zone& zone, double theta_step_deg, double phi_step_deg) {
  if (!(theta_step_deg > 0 && theta_step_deg <= 10 && phi_step_deg > 0 && phi_step_deg <= 10)) {
    throw InputError("exitant grid steps must be in (0, 10] deg");
  }
  ExitantGrid g;
  g.theta_min_rad = zone.theta_min_rad();
  g.theta_max_rad = zone.theta_max_rad();
  g.theta_step_rad = DegToRad(theta_step_deg);
  // Counted in double first: a damaged file's tiny step would overflow an int (fuzz/zonal_exr_fuzz).
  const double rows = std::ceil((g.theta_max_rad - g.theta_min_rad) / g.theta_step_rad - 1e-9);
  const double columns = std::round(360.0 / phi_step_deg);
  if (!(rows <= 1e5 && columns <= 1e5)) {
    std::string message = "exitant grid steps of ";
    message += std::to_string(theta_step_deg);
    message += " and ";
    message += std::to_string(phi_step_deg);
    message += " deg give an absurdly fine grid (more than 1e5 rows or columns)";
    throw InputError(message);
  }
  g.n_theta = static_cast<int>(rows);
  g.n_phi = static_cast<int>(columns);
  g.phi_step_rad = 2 * M_PI / g.n_phi;
  if (g.n_theta < 1) throw InputError("zone narrower than one theta step of the exitant grid");
  return g;
}

PixelToGrid::PixelToGrid(const RigCalibration& c, const ExitantGrid& grid, int subsamples)
    : grid_(grid) {
  const int w = c.camera_width, h = c.camera_height;
  const int pixels = w * h;
  channel_.resize(pixels);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) channel_[y * w + x] = static_cast<int8_t>(BayerChannel(c.layout, x, y));
  }
  std::vector<std::vector<Splat>> rows(h);
  ParallelFor(h, 8, [&](int64_t y0, int64_t y1) {
    std::vector<Splat> local;
    for (int64_t y = y0; y < y1; ++y) {
      for (int x = 0; x < w; ++x) {
        const int p = static_cast<int>(y) * w + x;
        if (!c.CameraValid(p) || c.camera_solid_angle_sr[p] <= 0) continue;
        Vec3 neighbour[3][3];
        NeighbourDirections(c.camera_direction, c.camera_response, w, h, x, static_cast<int>(y),
                            neighbour);
        const float part = c.camera_solid_angle_sr[p] / (subsamples * subsamples);
        local.clear();
        for (int sj = 0; sj < subsamples; ++sj) {
          for (int si = 0; si < subsamples; ++si) {
            const Vec3 d = InterpolateFootprint(neighbour, (si + 0.5) / subsamples - 0.5,
                                                (sj + 0.5) / subsamples - 0.5);
            const int cell = grid_.CellOf(d);
            if (cell < 0) continue;
            auto it = std::find_if(local.begin(), local.end(), [&](const Splat& s) { return s.cell == cell; });
            if (it == local.end()) local.push_back({cell, part});
            else it->weight += part;
          }
        }
        for (const Splat& s : local) rows[y].push_back({-1 - p, 0.0f}), rows[y].push_back(s);
      }
    }
  });
  // Flatten; entries with a negative cell mark the start of a pixel's splats.
  begin_.assign(pixels + 1, 0);
  std::vector<int64_t> count(pixels, 0);
  for (const auto& row : rows) {
    int current = -1;
    for (const Splat& s : row) {
      if (s.cell < 0) {
        current = -1 - s.cell;
        continue;
      }
      ++count[current];
      splats_.push_back(s);
    }
  }
  int64_t offset = 0;
  for (int p = 0; p < pixels; ++p) {
    begin_[p] = offset;
    offset += count[p];
  }
  begin_[pixels] = offset;
}

GridImage PixelToGrid::Resample(const std::vector<float>& value, const std::vector<float>& variance,
                                const std::vector<uint8_t>& valid) const {
  const int cells = grid_.cells();
  std::array<std::vector<double>, 3> sum, sum_var, weight;
  for (int ch = 0; ch < 3; ++ch) {
    sum[ch].assign(cells, 0.0);
    sum_var[ch].assign(cells, 0.0);
    weight[ch].assign(cells, 0.0);
  }
  const int pixels = static_cast<int>(begin_.size()) - 1;
  for (int p = 0; p < pixels; ++p) {
    if (begin_[p] == begin_[p + 1] || !valid[p]) continue;
    const int ch = channel_[p];
    for (int64_t e = begin_[p]; e < begin_[p + 1]; ++e) {
      const Splat& s = splats_[e];
      for (int c = ch < 0 ? 0 : ch; c <= (ch < 0 ? 2 : ch); ++c) {
        sum[c][s.cell] += s.weight * value[p];
        sum_var[c][s.cell] += static_cast<double>(s.weight) * s.weight * variance[p];
        weight[c][s.cell] += s.weight;
      }
    }
  }
  GridImage out;
  out.filled.assign(cells, 0);
  for (int ch = 0; ch < 3; ++ch) {
    out.value[ch].assign(cells, 0.0f);
    out.variance[ch].assign(cells, 0.0f);
    out.weight[ch].assign(cells, 0.0f);
    for (int k = 0; k < cells; ++k) {
      if (weight[ch][k] <= 0) continue;
      out.value[ch][k] = static_cast<float>(sum[ch][k] / weight[ch][k]);
      out.variance[ch][k] = static_cast<float>(sum_var[ch][k] / (weight[ch][k] * weight[ch][k]));
      out.weight[ch][k] = static_cast<float>(weight[ch][k]);
    }
    // Fill empty cells along their theta row (periodic in phi), else from the nearest row.
    for (int i = 0; i < grid_.n_theta; ++i) {
      const int base = i * grid_.n_phi;
      std::vector<int> known;
      for (int j = 0; j < grid_.n_phi; ++j) {
        if (weight[ch][base + j] > 0) known.push_back(j);
      }
      if (known.empty()) continue;
      for (int j = 0; j < grid_.n_phi; ++j) {
        if (weight[ch][base + j] > 0) continue;
        // Neighbours on both sides, wrapping around.
        auto after = std::upper_bound(known.begin(), known.end(), j);
        const int next = after == known.end() ? known.front() + grid_.n_phi : *after;
        const int prev = after == known.begin() ? known.back() - grid_.n_phi : *(after - 1);
        const double t = static_cast<double>(j - prev) / (next - prev);
        const int a = base + ((prev % grid_.n_phi) + grid_.n_phi) % grid_.n_phi;
        const int b = base + next % grid_.n_phi;
        out.value[ch][base + j] = static_cast<float>((1 - t) * out.value[ch][a] + t * out.value[ch][b]);
        out.variance[ch][base + j] =
            static_cast<float>((1 - t) * out.variance[ch][a] + t * out.variance[ch][b]);
        out.filled[base + j] = 1;
      }
    }
    for (int i = 0; i < grid_.n_theta; ++i) {
      const int base = i * grid_.n_phi;
      bool empty = true;
      for (int j = 0; j < grid_.n_phi && empty; ++j) empty = weight[ch][base + j] <= 0 && !out.filled[base + j];
      if (!empty) continue;
      // A whole row without data: copy the nearest row that has some.
      for (int d = 1; d < grid_.n_theta; ++d) {
        for (int src : {i - d, i + d}) {
          if (src < 0 || src >= grid_.n_theta) continue;
          bool has = false;
          for (int j = 0; j < grid_.n_phi && !has; ++j) has = weight[ch][src * grid_.n_phi + j] > 0 || out.filled[src * grid_.n_phi + j];
          if (!has) continue;
          for (int j = 0; j < grid_.n_phi; ++j) {
            out.value[ch][base + j] = out.value[ch][src * grid_.n_phi + j];
            out.variance[ch][base + j] = out.variance[ch][src * grid_.n_phi + j];
            out.filled[base + j] = 1;
          }
          d = grid_.n_theta;
          break;
        }
      }
    }
  }
  return out;
}

Eigen::MatrixXd CellIntegrals(const ExitantGrid& grid, const ZonalBasis& zb) {
  const int n = zb.size();
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(grid.cells(), n);
  // Per cell: Gauss-Legendre in cos(theta) x Gauss-Legendre in phi. The Z_lm with odd m carry a
  // factor sqrt(1 - t^2) that has a square-root singularity at the zone's edges, so the first
  // and the last row integrate in u with cos(theta) = edge -+ (row width) u^2, which makes the
  // integrand smooth (polynomial for the Z_lm); inside rows the integrand is smooth already.
  constexpr int kNodes = 6;
  const GaussLegendreRule rule = GaussLegendre(kNodes);
  const double lower = zb.zone().cos_lower(), upper = zb.zone().cos_upper();
  std::vector<double> z(n);
  for (int i = 0; i < grid.n_theta; ++i) {
    const double c0 = std::cos(grid.ThetaHigh(i)), c1 = std::cos(grid.ThetaLow(i));
    const bool at_upper = i == 0, at_lower = i == grid.n_theta - 1;
    double xs[kNodes], wx[kNodes];
    for (int q = 0; q < kNodes; ++q) {
      const double u = 0.5 * (rule.nodes[q] + 1);  // in [0, 1]
      if (at_upper && !at_lower) {
        xs[q] = upper - (upper - c0) * u * u;
        wx[q] = 0.5 * rule.weights[q] * 2 * (upper - c0) * u;
      } else if (at_lower && !at_upper) {
        xs[q] = lower + (c1 - lower) * u * u;
        wx[q] = 0.5 * rule.weights[q] * 2 * (c1 - lower) * u;
      } else {
        xs[q] = c0 + (c1 - c0) * u;
        wx[q] = 0.5 * rule.weights[q] * (c1 - c0);
      }
    }
    for (int j = 0; j < grid.n_phi; ++j) {
      for (int qi = 0; qi < kNodes; ++qi) {
        for (int qj = 0; qj < kNodes; ++qj) {
          const double phi = (j + 0.5 + 0.5 * rule.nodes[qj]) * grid.phi_step_rad;
          const double weight = wx[qi] * 0.5 * rule.weights[qj] * grid.phi_step_rad;
          zb.Eval(xs[qi], phi, z.data());
          for (int k = 0; k < n; ++k) a(i * grid.n_phi + j, k) += weight * z[k];
        }
      }
    }
  }
  return a;
}

void CheckExitantGrid(const Zone& zone, int order, double theta_step_deg, double phi_step_deg) {
  const ExitantGrid grid = MakeExitantGrid(zone, theta_step_deg, phi_step_deg);
  char text[200];
  std::snprintf(text, sizeof(text),
                "an exitant grid of %g x %g deg cells has %d rows and %d columns on the zone; "
                "order %d needs at least %d and %d: choose smaller --grid cells",
                theta_step_deg, phi_step_deg, grid.n_theta, grid.n_phi, order, order + 1,
                2 * order + 1);
  if (grid.n_theta < order + 1 || grid.n_phi < 2 * order + 1) throw InputError(text);
}

void ProjectExitant(ZonalData* data) {
  const ZonalBasis zb(data->zone(), data->order);
  const Eigen::MatrixXd a = CellIntegrals(data->grid, zb);
  const int n = zb.size(), cells = data->grid.cells();
  // Least squares for band-limited cell averages: G = A^T D^-1 A (D = cell solid angles) is the
  // Gram matrix of the cell-averaged basis, and M = A G^-1 maps cell values to coefficients.
  Eigen::VectorXd inv_area(cells);
  for (int c = 0; c < cells; ++c) inv_area[c] = 1 / data->grid.CellSolidAngle(c / data->grid.n_phi);
  const Eigen::MatrixXd gram = a.transpose() * inv_area.asDiagonal() * a;
  const Eigen::LLT<Eigen::MatrixXd> llt(gram);
  if (llt.info() != Eigen::Success) {
    throw InputError("the exitant grid is too coarse for order " + std::to_string(data->order) +
                     ": choose smaller --grid cells");
  }
  const Eigen::MatrixXd m = llt.solve(a.transpose()).transpose();  // cells x n
  const Eigen::MatrixXd m2 = m.cwiseProduct(m);
  for (int ch = 0; ch < 3; ++ch) {
    Eigen::MatrixXd values(n, cells), variances(n, cells);
    for (int k = 0; k < n; ++k) {
      for (int c = 0; c < cells; ++c) {
        values(k, c) = data->functions[k].value[ch][c];
        variances(k, c) = data->functions[k].variance[ch][c];
      }
    }
    data->tensor[ch] = values * m;
    data->tensor_variance[ch] = variances * m2;
  }
}

// ---------------------------------------------------------------------------------------------
namespace {

std::string FunctionLayer(int k) {
  int l, m;
  ShDegreeOrder(k, &l, &m);
  char name[32];
  std::snprintf(name, sizeof(name), "Z%d_%d", l, m);
  return name;
}

// Where `data` holds a value float storage cannot keep finite (NaN, Inf, or beyond FLT_MAX) or
// a negative variance: "" if nowhere, else the first such place, for error messages.
std::string FirstInvalidValue(const ZonalData& data) {
  const auto text = [](double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof(buffer), "%.6g", v);
    return std::string(buffer);
  };
  const auto bad = [](double v, bool variance) {
    const float f = static_cast<float>(v);
    return !std::isfinite(f) || (variance && f < 0);
  };
  for (size_t k = 0; k < data.functions.size(); ++k) {
    for (int ch = 0; ch < 3; ++ch) {
      const std::vector<float>& value = data.functions[k].value[ch];
      const std::vector<float>& variance = data.functions[k].variance[ch];
      for (size_t c = 0; c < value.size(); ++c) {
        if (bad(value[c], false)) {
          return "grid value " + FunctionLayer(static_cast<int>(k)) + "." + kRgbChannelNames[ch] +
                 " at cell " + std::to_string(c) + " is " + text(value[c]);
        }
      }
      for (size_t c = 0; c < variance.size(); ++c) {
        if (bad(variance[c], true)) {
          return "grid variance " + FunctionLayer(static_cast<int>(k)) + ".var." +
                 kRgbChannelNames[ch] + " at cell " + std::to_string(c) + " is " +
                 text(variance[c]);
        }
      }
    }
  }
  for (int ch = 0; ch < 3; ++ch) {
    for (int variance = 0; variance < 2; ++variance) {
      const Eigen::MatrixXd& m = variance ? data.tensor_variance[ch] : data.tensor[ch];
      for (Eigen::Index k = 0; k < m.rows(); ++k) {
        for (Eigen::Index j = 0; j < m.cols(); ++j) {
          if (bad(m(k, j), variance)) {
            return std::string("tensor ") + (variance ? "variance var." : "coefficient z.") +
                   kRgbChannelNames[ch] + "(" + std::to_string(k) + ", " + std::to_string(j) +
                   ") is " + text(m(k, j));
          }
        }
      }
    }
  }
  return "";
}

}  // namespace

void WriteZonalExr(const std::string& path, const ZonalData& data) {
  // Never write a NaN: a non-finite coefficient is a numerical failure upstream, and a file
  // holding one would only fail later, far from its cause.
  if (const std::string invalid = FirstInvalidValue(data); !invalid.empty()) {
    throw NumericalError("zonal data for " + path + " not written: " + invalid +
                         " (non-finite, beyond float range, or a negative variance); the frames "
                         "or the calibration that produced them are damaged: check them and "
                         "re-process the session (zbrdf process)");
  }
  const ExitantGrid& g = data.grid;
  const int n = static_cast<int>(data.functions.size());
  const int cells = g.cells();
  TwoPartExrWriter writer("grid", g.n_phi, g.n_theta, "tensor", n);
  writer.SetString("zbrdf.format", "zbrdf-zonal-v1");
  writer.SetDouble("zbrdf.theta_min_rad", data.theta_min_rad);
  writer.SetDouble("zbrdf.theta_max_rad", data.theta_max_rad);
  writer.SetInt("zbrdf.order", data.order);
  writer.SetDouble("zbrdf.theta_step_rad", g.theta_step_rad);
  writer.SetDouble("zbrdf.phi_step_rad", g.phi_step_rad);
  writer.SetString("zbrdf.attributes", data.attributes.dump());
  for (int k = 0; k < n; ++k) {
    const std::string layer = FunctionLayer(k);
    for (int ch = 0; ch < 3; ++ch) {
      writer.AddImageChannel(layer + "." + kRgbChannelNames[ch], data.functions[k].value[ch]);
      writer.AddImageChannel(layer + ".var." + kRgbChannelNames[ch],
                             data.functions[k].variance[ch]);
    }
  }
  if (n > 0) {
    for (int ch = 0; ch < 3; ++ch) {
      writer.AddImageChannel(std::string("weight.") + kRgbChannelNames[ch],
                             data.functions[0].weight[ch]);
    }
    std::vector<float> filled(cells);
    for (int c = 0; c < cells; ++c) filled[c] = data.functions[0].filled[c];
    writer.AddImageChannel("filled", std::move(filled));
  }
  for (int ch = 0; ch < 3; ++ch) {
    std::vector<float> v(static_cast<size_t>(n) * n), var(static_cast<size_t>(n) * n);
    for (int k = 0; k < n; ++k) {
      for (int j = 0; j < n; ++j) {
        v[k * n + j] = static_cast<float>(data.tensor[ch](k, j));
        var[k * n + j] = static_cast<float>(data.tensor_variance[ch](k, j));
      }
    }
    writer.AddTensorChannel(std::string("z.") + kRgbChannelNames[ch], std::move(v));
    writer.AddTensorChannel(std::string("var.") + kRgbChannelNames[ch], std::move(var));
  }
  writer.Write(path, path);
}

ZonalData ReadZonalExr(const std::string& path) {
  ZonalData data;
  CheckExrHeaderSizes(path, path);
  try {
    Imf::MultiPartInputFile file(path.c_str());
    int grid_part = -1, tensor_part = -1;
    for (int i = 0; i < file.parts(); ++i) {
      if (file.header(i).hasName() && file.header(i).name() == "grid") grid_part = i;
      if (file.header(i).hasName() && file.header(i).name() == "tensor") tensor_part = i;
    }
    if (grid_part < 0 || tensor_part < 0) {
      throw InputError(path + " is not a zbrdf zonal file (no 'grid' and 'tensor' parts)");
    }
    const Imf::Header& h = file.header(grid_part);
    const auto* format = h.findTypedAttribute<Imf::StringAttribute>("zbrdf.format");
    if (!format || format->value() != "zbrdf-zonal-v1") {
      throw InputError(path + " is not a zbrdf zonal file (zbrdf.format missing or unknown)");
    }
    auto get_double = [&](const char* name) {
      const auto* a = h.findTypedAttribute<Imf::DoubleAttribute>(name);
      if (!a) throw InputError(path + ": header attribute " + name + " is missing");
      return a->value();
    };
    data.theta_min_rad = get_double("zbrdf.theta_min_rad");
    data.theta_max_rad = get_double("zbrdf.theta_max_rad");
    const auto* order = h.findTypedAttribute<Imf::IntAttribute>("zbrdf.order");
    if (!order || order->value() < 0 || order->value() > 30) {
      throw InputError(path + ": header attribute zbrdf.order is missing or out of range");
    }
    data.order = order->value();
    const auto* attributes = h.findTypedAttribute<Imf::StringAttribute>("zbrdf.attributes");
    if (attributes) data.attributes = nlohmann::json::parse(attributes->value(), nullptr, false);
    const Zone zone(data.theta_min_rad, data.theta_max_rad);
    data.grid = MakeExitantGrid(zone, RadToDeg(get_double("zbrdf.theta_step_rad")),
                                RadToDeg(get_double("zbrdf.phi_step_rad")));
    const Imath::Box2i window = h.dataWindow();
    RequireWindowAtOrigin(window.min.x, window.min.y, window.max.x, window.max.y, path, "grid");
    if (window.max.x - window.min.x + 1 != data.grid.n_phi ||
        window.max.y - window.min.y + 1 != data.grid.n_theta) {
      throw InputError(path + ": grid part is not n_phi x n_theta as its header says");
    }
    const int n = ShCount(data.order), cells = data.grid.cells();
    data.functions.resize(n);
    Imf::FrameBuffer fb;
    auto slice = [&](Imf::FrameBuffer& frame, const Imf::Header& header, const std::string& name,
                     std::vector<float>& target, int width, int count, int origin_x, int origin_y) {
      if (!header.channels().findChannel(name)) {
        throw InputError(path + ": channel " + name + " is missing");
      }
      target.assign(count, 0.0f);
      char* base = reinterpret_cast<char*>(target.data()) -
                   (static_cast<ptrdiff_t>(origin_y) * width + origin_x) * sizeof(float);
      frame.insert(name, Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * width));
    };
    std::vector<float> filled;
    for (int k = 0; k < n; ++k) {
      const std::string layer = FunctionLayer(k);
      for (int ch = 0; ch < 3; ++ch) {
        slice(fb, h, layer + "." + kRgbChannelNames[ch], data.functions[k].value[ch],
              data.grid.n_phi, cells, window.min.x, window.min.y);
        slice(fb, h, layer + ".var." + kRgbChannelNames[ch], data.functions[k].variance[ch],
              data.grid.n_phi, cells, window.min.x, window.min.y);
      }
    }
    std::array<std::vector<float>, 3> weight;
    for (int ch = 0; ch < 3; ++ch) {
      slice(fb, h, std::string("weight.") + kRgbChannelNames[ch], weight[ch], data.grid.n_phi,
            cells, window.min.x, window.min.y);
    }
    slice(fb, h, "filled", filled, data.grid.n_phi, cells, window.min.x, window.min.y);
    Imf::InputPart grid(file, grid_part);
    grid.setFrameBuffer(fb);
    grid.readPixels(window.min.y, window.max.y);
    for (int k = 0; k < n; ++k) {
      data.functions[k].weight = weight;
      data.functions[k].filled.resize(cells);
      for (int c = 0; c < cells; ++c) data.functions[k].filled[c] = filled[c] != 0;
    }
    const Imf::Header& th = file.header(tensor_part);
    const Imath::Box2i tw = th.dataWindow();
    RequireWindowAtOrigin(tw.min.x, tw.min.y, tw.max.x, tw.max.y, path, "tensor");
    if (tw.max.x - tw.min.x + 1 != n || tw.max.y - tw.min.y + 1 != n) {
      throw InputError(path + ": tensor part is not n x n for order " + std::to_string(data.order));
    }
    Imf::FrameBuffer tfb;
    std::array<std::vector<float>, 3> tv, tvar;
    for (int ch = 0; ch < 3; ++ch) {
      slice(tfb, th, std::string("z.") + kRgbChannelNames[ch], tv[ch], n, n * n, tw.min.x,
            tw.min.y);
      slice(tfb, th, std::string("var.") + kRgbChannelNames[ch], tvar[ch], n, n * n, tw.min.x,
            tw.min.y);
    }
    Imf::InputPart tensor(file, tensor_part);
    tensor.setFrameBuffer(tfb);
    tensor.readPixels(tw.min.y, tw.max.y);
    for (int ch = 0; ch < 3; ++ch) {
      data.tensor[ch].resize(n, n);
      data.tensor_variance[ch].resize(n, n);
      for (int k = 0; k < n; ++k) {
        for (int j = 0; j < n; ++j) {
          data.tensor[ch](k, j) = tv[ch][k * n + j];
          data.tensor_variance[ch](k, j) = tvar[ch][k * n + j];
        }
      }
    }
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError("cannot read zonal file " + path + ": " + e.what());
  }
  // Values, variances and the tensor alike: a damaged file must not reach the conversion or
  // the fits (which would turn one NaN into NaN everywhere).
  if (const std::string invalid = FirstInvalidValue(data); !invalid.empty()) {
    throw InputError(path + " holds an invalid value: " + invalid +
                     "; the file is damaged: re-process the session (zbrdf process)");
  }
  return data;
}

}  // namespace zbrdf
