#include "brdf/bilinear_warp.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "basis/error.h"

namespace zbrdf {
namespace {

// Smallest root in [0, 1] of a t + (b - a) t^2 / 2 = v, the integral over [0, t] of the linear
// density from a (at 0) to b (at 1). Written as 2v / (a + sqrt(a^2 + 2 (b - a) v)), which has no
// cancellation for either sign of b - a and tends to v / a as b -> a.
double InvertLinearIntegral(double a, double b, double v) {
  const double discriminant = std::max(0.0, a * a + 2.0 * (b - a) * v);
  const double denominator = a + std::sqrt(discriminant);
  if (!(denominator > 0)) return 0.0;
  return std::clamp(2.0 * v / denominator, 0.0, 1.0);
}

// The largest i in [0, n - 2] with below(i) true, for a predicate that is true up to some index
// and false after it (a binary search over ascending CDF nodes); 0 if below(1) is false. For
// CDFs the predicate is cdf[i] < u, so that u = 1 falls in the last cell with mass, not in a
// zero-mass tail.
template <typename Predicate>
int FindInterval(int n, const Predicate& below) {
  int lo = 0, hi = n - 2;  // below(lo) is taken as true
  while (lo < hi) {
    const int mid = (lo + hi + 1) / 2;
    if (below(mid)) {
      lo = mid;
    } else {
      hi = mid - 1;
    }
  }
  return lo;
}

// Cell index (0 .. n - 2) and fraction for a coordinate in [0, 1] on n nodes.
void Locate(double coordinate, int n, int* cell, double* fraction) {
  const double p = std::clamp(coordinate, 0.0, 1.0) * (n - 1);
  *cell = std::min(static_cast<int>(p), n - 2);
  *fraction = p - *cell;
}

}  // namespace

BilinearWarp2D::BilinearWarp2D(int nx, int ny, std::span<const float> values,
                               std::vector<std::vector<float>> param_values, bool normalize)
    : nx_(nx), ny_(ny), param_values_(std::move(param_values)), normalized_(normalize) {
  if (nx < 2 || ny < 2) {
    throw InputError("bilinear warp: the grid must be at least 2 x 2 nodes (got " +
                     std::to_string(nx) + " x " + std::to_string(ny) + ")");
  }
  int slices = 1;
  param_strides_.assign(param_values_.size(), 0);
  for (int d = static_cast<int>(param_values_.size()) - 1; d >= 0; --d) {
    const auto& nodes = param_values_[d];
    if (nodes.empty())
      throw InputError("bilinear warp: parameter " + std::to_string(d) + " has no node");
    for (size_t k = 1; k < nodes.size(); ++k) {
      if (!(nodes[k] > nodes[k - 1])) {
        throw InputError("bilinear warp: the nodes of parameter " + std::to_string(d) +
                         " must be strictly ascending");
      }
    }
    param_strides_[d] = nodes.size() > 1 ? slices : 0;
    slices *= static_cast<int>(nodes.size());
  }
  const size_t slice_size = static_cast<size_t>(nx) * ny;
  if (values.size() != slices * slice_size) {
    throw InputError("bilinear warp: " + std::to_string(values.size()) + " values, expected " +
                     std::to_string(slices * slice_size));
  }
  data_.assign(values.begin(), values.end());
  if (!normalize) return;
  conditional_.resize(data_.size());
  marginal_.resize(static_cast<size_t>(slices) * ny);
  const double cells = static_cast<double>(nx - 1) * (ny - 1);
  for (int s = 0; s < slices; ++s) {
    double* d = &data_[s * slice_size];
    for (size_t i = 0; i < slice_size; ++i) {
      if (!(d[i] >= 0) || !std::isfinite(d[i])) {
        throw InputError("bilinear warp: a density value is negative or not finite (" +
                         std::to_string(d[i]) + ")");
      }
    }
    // Integral of the bilinear interpolant in index units: the mean of each cell's corners.
    double total = 0;
    for (int y = 0; y + 1 < ny; ++y) {
      for (int x = 0; x + 1 < nx; ++x) {
        const size_t i = static_cast<size_t>(y) * nx + x;
        total += 0.25 * (d[i] + d[i + 1] + d[i + nx] + d[i + nx + 1]);
      }
    }
    if (!(total > 0)) {
      std::fill(d, d + slice_size, 1.0);
      total = cells;
    }
    // Scale to a density over [0, 1]^2: index-unit integral = cells.
    for (size_t i = 0; i < slice_size; ++i) d[i] *= cells / total;
    double* c = &conditional_[s * slice_size];
    double* m = &marginal_[static_cast<size_t>(s) * ny];
    for (int y = 0; y < ny; ++y) {
      double sum = 0;
      c[static_cast<size_t>(y) * nx] = 0;
      for (int x = 0; x + 1 < nx; ++x) {
        const size_t i = static_cast<size_t>(y) * nx + x;
        sum += 0.5 * (d[i] + d[i + 1]);
        c[i + 1] = sum;
      }
    }
    m[0] = 0;
    for (int y = 0; y + 1 < ny; ++y) {
      m[y + 1] = m[y] + 0.5 * (c[static_cast<size_t>(y) * nx + nx - 1] +
                               c[static_cast<size_t>(y + 1) * nx + nx - 1]);
    }
  }
}

BilinearWarp2D::Blend BilinearWarp2D::BlendFor(std::span<const double> params) const {
  Blend blend;
  blend.slices = {0};
  blend.weights = {1.0};
  if (params.size() < param_values_.size()) {
    throw InternalError("bilinear warp: " + std::to_string(param_values_.size()) +
                        " parameters expected, got " + std::to_string(params.size()));
  }
  for (size_t d = 0; d < param_values_.size(); ++d) {
    const auto& nodes = param_values_[d];
    if (nodes.size() == 1) continue;
    const int n = static_cast<int>(nodes.size());
    const int index = FindInterval(n, [&](int i) { return nodes[i] <= params[d]; });
    const double w1 =
        std::clamp((params[d] - nodes[index]) / (nodes[index + 1] - nodes[index]), 0.0, 1.0);
    const size_t count = blend.slices.size();
    for (size_t k = 0; k < count; ++k) {
      blend.slices.push_back(blend.slices[k] + (index + 1) * param_strides_[d]);
      blend.weights.push_back(blend.weights[k] * w1);
      blend.slices[k] += index * param_strides_[d];
      blend.weights[k] *= 1.0 - w1;
    }
  }
  return blend;
}

double BilinearWarp2D::Data(const Blend& b, int x, int y) const {
  const size_t slice_size = static_cast<size_t>(nx_) * ny_;
  double v = 0;
  for (size_t k = 0; k < b.slices.size(); ++k) {
    v += b.weights[k] * data_[b.slices[k] * slice_size + static_cast<size_t>(y) * nx_ + x];
  }
  return v;
}

double BilinearWarp2D::Conditional(const Blend& b, int x, int y) const {
  const size_t slice_size = static_cast<size_t>(nx_) * ny_;
  double v = 0;
  for (size_t k = 0; k < b.slices.size(); ++k) {
    v += b.weights[k] * conditional_[b.slices[k] * slice_size + static_cast<size_t>(y) * nx_ + x];
  }
  return v;
}

double BilinearWarp2D::Marginal(const Blend& b, int y) const {
  double v = 0;
  for (size_t k = 0; k < b.slices.size(); ++k) {
    v += b.weights[k] * marginal_[static_cast<size_t>(b.slices[k]) * ny_ + y];
  }
  return v;
}

double BilinearWarp2D::Eval(std::array<double, 2> pos, std::span<const double> params) const {
  const Blend b = BlendFor(params);
  int x, y;
  double s, t;
  Locate(pos[0], nx_, &x, &s);
  Locate(pos[1], ny_, &y, &t);
  return (1 - t) * ((1 - s) * Data(b, x, y) + s * Data(b, x + 1, y)) +
         t * ((1 - s) * Data(b, x, y + 1) + s * Data(b, x + 1, y + 1));
}

std::array<double, 3> BilinearWarp2D::Sample(std::array<double, 2> u,
                                             std::span<const double> params) const {
  ZBRDF_ASSERT(normalized_, "Sample() needs a normalized warp");
  const Blend b = BlendFor(params);
  const double cells = static_cast<double>(nx_ - 1) * (ny_ - 1);
  // Rows: the marginal is piecewise linear between row nodes.
  double uy = std::clamp(u[1], 0.0, 1.0) * cells;
  const int row = FindInterval(ny_, [&](int y) { return Marginal(b, y) < uy; });
  uy -= Marginal(b, row);
  const double r0 = Conditional(b, nx_ - 1, row), r1 = Conditional(b, nx_ - 1, row + 1);
  const double t = InvertLinearIntegral(r0, r1, uy);
  // Columns, given the row position t.
  double ux = std::clamp(u[0], 0.0, 1.0) * ((1 - t) * r0 + t * r1);
  auto row_cdf = [&](int x) {
    return (1 - t) * Conditional(b, x, row) + t * Conditional(b, x, row + 1);
  };
  const int col = FindInterval(nx_, [&](int x) { return row_cdf(x) < ux; });
  ux -= row_cdf(col);
  const double c0 = (1 - t) * Data(b, col, row) + t * Data(b, col, row + 1);
  const double c1 = (1 - t) * Data(b, col + 1, row) + t * Data(b, col + 1, row + 1);
  const double s = InvertLinearIntegral(c0, c1, ux);
  return {(col + s) / (nx_ - 1), (row + t) / (ny_ - 1), (1 - s) * c0 + s * c1};
}

std::array<double, 3> BilinearWarp2D::Invert(std::array<double, 2> pos,
                                             std::span<const double> params) const {
  ZBRDF_ASSERT(normalized_, "Invert() needs a normalized warp");
  const Blend b = BlendFor(params);
  int col, row;
  double s, t;
  Locate(pos[0], nx_, &col, &s);
  Locate(pos[1], ny_, &row, &t);
  const double c0 = (1 - t) * Data(b, col, row) + t * Data(b, col, row + 1);
  const double c1 = (1 - t) * Data(b, col + 1, row) + t * Data(b, col + 1, row + 1);
  const double density = (1 - s) * c0 + s * c1;
  const double r0 = Conditional(b, nx_ - 1, row), r1 = Conditional(b, nx_ - 1, row + 1);
  const double row_total = (1 - t) * r0 + t * r1;
  double ux = s * (c0 + 0.5 * s * (c1 - c0)) + (1 - t) * Conditional(b, col, row) +
              t * Conditional(b, col, row + 1);
  ux = row_total > 0 ? ux / row_total : 0.0;
  const double uy = t * (r0 + 0.5 * t * (r1 - r0)) + Marginal(b, row);
  const double cells = static_cast<double>(nx_ - 1) * (ny_ - 1);
  return {std::clamp(ux, 0.0, 1.0), std::clamp(uy / cells, 0.0, 1.0), density};
}

}  // namespace zbrdf
