#include "brdf/sampling.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "basis/error.h"

namespace zbrdf {
namespace {

// The largest double below 1: keeps remapped and sampled coordinates inside [0, 1).
constexpr double kOneMinusEpsilon = 0x1.fffffffffffffp-1;

std::vector<double> RowSums(std::span<const double> weights, int nx, int ny) {
  std::vector<double> sums(ny, 0.0);
  for (int iy = 0; iy < ny; ++iy) {
    for (int ix = 0; ix < nx; ++ix) sums[iy] += weights[static_cast<size_t>(iy) * nx + ix];
  }
  return sums;
}

std::span<const double> CheckedWeights2D(std::span<const double> weights, int nx, int ny) {
  if (nx < 1 || ny < 1 || weights.size() != static_cast<size_t>(nx) * ny) {
    throw InputError("Distribution2D: expected nx * ny = " + std::to_string(nx) + " * " +
                     std::to_string(ny) + " weights, got " + std::to_string(weights.size()));
  }
  return weights;
}

}  // namespace

Distribution1D::Distribution1D(std::span<const double> weights)
    : weights_(weights.begin(), weights.end()), cdf_(weights.size() + 1, 0.0) {
  if (weights_.empty()) throw InputError("Distribution1D: needs at least one weight");
  for (size_t i = 0; i < weights_.size(); ++i) {
    if (!std::isfinite(weights_[i]) || weights_[i] < 0) {
      throw InputError("Distribution1D: weight " + std::to_string(i) +
                       " must be finite and >= 0 (got " + std::to_string(weights_[i]) + ")");
    }
    cdf_[i + 1] = cdf_[i] + weights_[i];
  }
  sum_ = cdf_.back();
  if (!(sum_ > 0) || !std::isfinite(sum_)) {
    throw InputError("Distribution1D: the weights must have a positive, finite sum");
  }
  // Cells after the last positive weight get cdf exactly 1, so that u < 1 never lands in them
  // through rounding of the running sum.
  size_t last = weights_.size();
  while (weights_[last - 1] == 0) --last;
  for (size_t i = 1; i <= weights_.size(); ++i) cdf_[i] = i >= last ? 1.0 : cdf_[i] / sum_;
  guide_.resize(weights_.size());
  for (size_t g = 0; g < guide_.size(); ++g) {
    guide_[g] = FindCellBySearch(static_cast<double>(g) / static_cast<double>(guide_.size()));
  }
}

int Distribution1D::FindCellBySearch(double u) const {
  // First cdf entry > u, minus one: cdf_[cell] <= u < cdf_[cell + 1], so the cell has a
  // positive weight.
  const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
  return std::clamp(static_cast<int>(it - cdf_.begin()) - 1, 0, size() - 1);
}

int Distribution1D::FindCell(double u) const {
  // FindCellBySearch(u), walked from the cell of u's guide entry: the walks over all guide
  // entries add up to size() + guide_.size() steps, so about two per call, where the binary
  // search's branches are unpredictable (the proxy sampler calls this for every sample).
  if (!(u >= 0 && u < 1)) return FindCellBySearch(u);  // NaN too
  const int n = size();
  int cell = guide_[std::min(static_cast<int>(u * n), n - 1)];
  while (cell > 0 && cdf_[cell] > u) --cell;  // u * n may round up into the next guide entry
  while (cell + 1 < n && cdf_[cell + 1] <= u) ++cell;
  return cell;
}

double Distribution1D::Sample(double u, double* pdf, int* cell) const {
  double u_cell = 0;
  const int index = SampleDiscrete(u, nullptr, &u_cell);
  if (pdf != nullptr) *pdf = weights_[index] * size() / sum_;
  if (cell != nullptr) *cell = index;
  // Keep x in its cell as Pdf() computes it (floor(x * n)), despite rounding.
  double x = std::min((index + u_cell) / size(), kOneMinusEpsilon);
  while (static_cast<int>(x * size()) > index) x = std::nextafter(x, 0.0);
  while (static_cast<int>(x * size()) < index) x = std::nextafter(x, 1.0);
  return x;
}

double Distribution1D::Pdf(double x) const {
  if (!(x >= 0 && x < 1)) return 0;
  const int index = std::min(static_cast<int>(x * size()), size() - 1);
  return weights_[index] * size() / sum_;
}

int Distribution1D::SampleDiscrete(double u, double* pmf, double* u_remapped) const {
  const int index = FindCell(u);
  if (pmf != nullptr) *pmf = weights_[index] / sum_;
  if (u_remapped != nullptr) {
    const double width = cdf_[index + 1] - cdf_[index];
    *u_remapped = std::clamp((u - cdf_[index]) / width, 0.0, kOneMinusEpsilon);
  }
  return index;
}

double Distribution1D::Pmf(int cell) const {
  if (cell < 0 || cell >= size()) return 0;
  return weights_[cell] / sum_;
}

Distribution2D::Distribution2D(std::span<const double> weights, int nx, int ny)
    : nx_(nx), ny_(ny), marginal_(RowSums(CheckedWeights2D(weights, nx, ny), nx, ny)) {
  rows_.reserve(ny);
  const std::vector<double> uniform(nx, 1.0);
  for (int iy = 0; iy < ny; ++iy) {
    const std::span<const double> row = weights.subspan(static_cast<size_t>(iy) * nx, nx);
    // A row of zeros is never chosen by the marginal; a uniform conditional keeps it valid.
    rows_.emplace_back(marginal_.Pmf(iy) > 0 ? row : std::span<const double>(uniform));
  }
}

std::array<double, 2> Distribution2D::Sample(double u0, double u1, double* pdf) const {
  double pdf_y = 0, pdf_x = 0;
  int iy = 0;
  const double y = marginal_.Sample(u1, &pdf_y, &iy);
  const double x = rows_[iy].Sample(u0, &pdf_x);
  if (pdf != nullptr) *pdf = pdf_x * pdf_y;
  return {x, y};
}

double Distribution2D::Pdf(double x, double y) const {
  if (!(x >= 0 && x < 1 && y >= 0 && y < 1)) return 0;
  const int iy = std::min(static_cast<int>(y * ny_), ny_ - 1);
  const double pdf_y = marginal_.Pdf(y);
  return pdf_y > 0 ? pdf_y * rows_[iy].Pdf(x) : 0.0;
}

double Distribution2D::CellProbability(int ix, int iy) const {
  if (iy < 0 || iy >= ny_) return 0;
  return marginal_.Pmf(iy) * rows_[iy].Pmf(ix);
}

bool UpperHalfVector(const Vec3& w_i, const Vec3& w_o, Vec3* h) {
  const Vec3 sum = w_i + w_o;
  const double length = Length(sum);
  if (!(length > 0)) return false;
  // One division for the three components (this is on every glossy pdf's path).
  const double inv = (sum.z < 0 ? -1.0 : 1.0) / length;
  *h = sum * inv;
  return true;
}

double HalfVectorToIncidentPdf(double pdf_h, const Vec3& w_o, const Vec3& h) {
  const double cos_oh = std::abs(Dot(w_o, h));
  return cos_oh > 0 ? pdf_h / (4.0 * cos_oh) : 0.0;
}

}  // namespace zbrdf
