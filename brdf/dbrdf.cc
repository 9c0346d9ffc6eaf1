#include "brdf/dbrdf.h"

#include <algorithm>
#include <functional>
#include <cmath>

#include "basis/error.h"
#include "brdf/fresnel.h"
#include "brdf/model_parameters.h"

namespace zbrdf {
namespace {

// Antiderivatives for the normalization integral of a piecewise-linear p(theta):
// G' = sin(theta) cos(theta), H' = theta sin(theta) cos(theta).
double G(double theta) { return 0.5 * std::sin(theta) * std::sin(theta); }
double H(double theta) {
  return -0.25 * theta * std::cos(2.0 * theta) + 0.125 * std::sin(2.0 * theta);
}

// params, after checking it; throws InputError (see the constructor's contract).
DBrdfParams Validated(DBrdfParams params) {
  if (const std::string problems = params.p_h.Problems(); !problems.empty()) {
    throw InputError(problems);
  }
  RequireNonNegative("dbrdf", "c", params.c);
  RequireInUnitInterval("dbrdf", "F0", params.f0);
  RequireNonNegative("dbrdf", "kd", params.kd);
  const double integral = params.p_h.NormalizationIntegral();
  if (!(std::abs(integral - 1.0) <= 1e-9)) {
    throw InputError(
        "dbrdf: p(h) must be normalized (integral p(h) cos(theta_h) dw_h = 1), but it "
        "integrates to " +
        FormatDouble(integral) + "; call HalfVectorTable::Normalize() and fold the scale into c");
  }
  return params;
}

std::vector<double> CosThetaNodes(const HalfVectorTable& table) {
  std::vector<double> nodes(table.theta_samples);
  for (int j = 0; j < table.theta_samples; ++j) nodes[j] = std::cos(j * table.ThetaStep());
  nodes.back() = 0.0;
  return nodes;
}

// Weight of the sampling cell (theta cell j, phi cell k): the largest p on its corners (so that
// the proposal is positive wherever the interpolated p is) times its projected solid angle,
// integral cos dw. Row-major over (j, k).
std::vector<double> CellWeights(const HalfVectorTable& table,
                                const std::vector<double>& cos_theta_nodes) {
  const int theta_cells = table.theta_samples - 1, phi_cells = table.phi_samples;
  std::vector<double> weights(static_cast<size_t>(theta_cells) * phi_cells);
  for (int j = 0; j < theta_cells; ++j) {
    const double c0 = cos_theta_nodes[j], c1 = cos_theta_nodes[j + 1];
    const double projected = 0.5 * (c0 * c0 - c1 * c1) * table.PhiStep();
    for (int k = 0; k < phi_cells; ++k) {
      const int k1 = (k + 1) % phi_cells;
      const double corner =
          std::max({table.At(j, k), table.At(j, k1), table.At(j + 1, k), table.At(j + 1, k1)});
      weights[static_cast<size_t>(j) * phi_cells + k] = corner * projected;
    }
  }
  return weights;
}

}  // namespace

HalfVectorTable HalfVectorTable::Isotropic(std::vector<double> p_by_theta) {
  HalfVectorTable table;
  table.theta_samples = static_cast<int>(p_by_theta.size());
  table.phi_samples = 1;
  table.p = std::move(p_by_theta);
  return table;
}

HalfVectorTable HalfVectorTable::Ggx(double alpha, int theta_samples) {
  ZBRDF_ASSERT(alpha > 0 && theta_samples >= 2, "HalfVectorTable::Ggx: bad alpha or node count");
  std::vector<double> p(theta_samples);
  for (int j = 0; j < theta_samples; ++j) {
    const double theta = 0.5 * M_PI * j / (theta_samples - 1);
    const double s = std::sin(theta), c = std::cos(theta);
    const double q = s * s / (alpha * alpha) + c * c;  // the same D, stable at grazing angles
    p[j] = 1.0 / (M_PI * alpha * alpha * q * q);
  }
  HalfVectorTable table = Isotropic(std::move(p));
  table.Normalize();
  return table;
}

double HalfVectorTable::ThetaStep() const { return 0.5 * M_PI / (theta_samples - 1); }
double HalfVectorTable::PhiStep() const { return 2.0 * M_PI / phi_samples; }

double HalfVectorTable::Eval(double theta_h_rad, double phi_h_rad) const {
  const double u = std::clamp(theta_h_rad, 0.0, 0.5 * M_PI) / ThetaStep();
  const int j = std::min(static_cast<int>(u), theta_samples - 2);
  const double t = u - j;
  if (phi_samples == 1) return (1.0 - t) * At(j, 0) + t * At(j + 1, 0);
  double v = std::fmod(phi_h_rad, 2.0 * M_PI) / PhiStep();
  if (v < 0) v += phi_samples;
  const int k0 = std::min(static_cast<int>(v), phi_samples - 1);
  const int k1 = (k0 + 1) % phi_samples;
  const double s = std::clamp(v - k0, 0.0, 1.0);
  const double lower = (1.0 - s) * At(j, k0) + s * At(j, k1);
  const double upper = (1.0 - s) * At(j + 1, k0) + s * At(j + 1, k1);
  return (1.0 - t) * lower + t * upper;
}

double HalfVectorTable::NormalizationIntegral() const {
  // Per theta interval, integral of ((1 - t) p_j + t p_j+1) sin cos dtheta = W0 p_j + W1 p_j+1;
  // over phi the periodic linear interpolant integrates to PhiStep() * sum_k p_jk exactly.
  const double step = ThetaStep();
  double total = 0;
  for (int j = 0; j + 1 < theta_samples; ++j) {
    const double a = j * step, b = (j + 1) * step;
    const double w1 = (H(b) - H(a) - a * (G(b) - G(a))) / step;
    const double w0 = (G(b) - G(a)) - w1;
    double sum_lower = 0, sum_upper = 0;
    for (int k = 0; k < phi_samples; ++k) {
      sum_lower += At(j, k);
      sum_upper += At(j + 1, k);
    }
    total += w0 * sum_lower + w1 * sum_upper;
  }
  return total * PhiStep();
}

void HalfVectorTable::Normalize() {
  const double integral = NormalizationIntegral();
  if (!(integral > 0) || !std::isfinite(integral)) {
    throw NumericalError("dbrdf: cannot normalize p(h): its integral p(h) cos(theta_h) dw_h is " +
                         FormatDouble(integral) + "; p needs a positive value somewhere");
  }
  for (double& value : p) value /= integral;
}

std::string HalfVectorTable::Problems() const {
  if (theta_samples < 2) {
    return "dbrdf: theta_samples must be >= 2 (got " + std::to_string(theta_samples) + ")";
  }
  if (phi_samples < 1) {
    return "dbrdf: phi_samples must be >= 1 (got " + std::to_string(phi_samples) + ")";
  }
  const size_t expected = static_cast<size_t>(theta_samples) * phi_samples;
  if (p.size() != expected) {
    return "dbrdf: p has " + std::to_string(p.size()) +
           " values, expected theta_samples * phi_samples = " + std::to_string(expected);
  }
  for (size_t i = 0; i < p.size(); ++i) {
    if (!std::isfinite(p[i]) || p[i] < 0) {
      return "dbrdf: p[" + std::to_string(i) + "] must be finite and >= 0 (got " +
             FormatDouble(p[i]) + ")";
    }
  }
  return "";
}

DBrdf::DBrdf(DBrdfParams params)
    : params_(Validated(std::move(params))),
      cos_theta_nodes_(CosThetaNodes(params_.p_h)),
      cells_(CellWeights(params_.p_h, cos_theta_nodes_), params_.p_h.phi_samples,
             params_.p_h.theta_samples - 1) {
  // The half-vector sampler's solid-angle density, constant per cell: its probability over its
  // solid angle.
  const HalfVectorTable& table = params_.p_h;
  cell_density_.resize(static_cast<size_t>(table.theta_samples - 1) * table.phi_samples);
  for (int j = 0; j + 1 < table.theta_samples; ++j) {
    const double solid_angle = (cos_theta_nodes_[j] - cos_theta_nodes_[j + 1]) * table.PhiStep();
    for (int k = 0; k < table.phi_samples; ++k) {
      cell_density_[static_cast<size_t>(j) * table.phi_samples + k] =
          cells_.CellProbability(k, j) / solid_angle;
    }
  }
}

Rgb DBrdf::Eval(const Vec3& w_i, const Vec3& w_o) const {
  if (w_i.z <= 0 || w_o.z <= 0) return {};
  const Vec3 h = Normalize(w_i + w_o);
  const double p = params_.p_h.Eval(SphericalTheta(h), SphericalPhi(h));
  const double denominator = w_i.z + w_o.z - w_i.z * w_o.z;
  const double specular = p * SchlickFresnel(params_.f0, Dot(w_i, h)) / denominator;
  return params_.c * specular + params_.kd / M_PI;
}

double DBrdf::HalfVectorPdf(const Vec3& h) const {
  const HalfVectorTable& table = params_.p_h;
  const int theta_cells = table.theta_samples - 1;
  // Cell j holds cos(theta_h) in (cos_theta_nodes_[j + 1], cos_theta_nodes_[j]]: a binary search
  // of the decreasing cosines instead of acos; an isotropic table needs no azimuth.
  const auto it = std::upper_bound(cos_theta_nodes_.begin(), cos_theta_nodes_.end(), h.z,
                                   std::greater<>());
  const int j = std::clamp(static_cast<int>(it - cos_theta_nodes_.begin()) - 1, 0,
                           theta_cells - 1);
  const int k = table.phi_samples == 1 ? 0
                                       : std::min(static_cast<int>(SphericalPhi(h) /
                                                                   table.PhiStep()),
                                                  table.phi_samples - 1);
  return cell_density_[static_cast<size_t>(j) * table.phi_samples + k];
}

double DBrdf::SpecularProbability(const Vec3& w_o) const {
  return SpecularLobeProbability(4.0 * params_.c.Average() * SchlickFresnel(params_.f0, w_o.z),
                                 params_.kd.Average());
}

BrdfSample DBrdf::Sample(const Vec3& w_o, double u_lobe, double u0, double u1) const {
  BrdfSample s;
  if (w_o.z <= 0) return s;
  s.w_i = SampleHalfVectorMixture(
      w_o, SpecularProbability(w_o), u_lobe, u0, u1, [&](double u, double v) {
        const auto [x, y] = cells_.Sample(u, v);
        const int theta_cells = cells_.ny();
        const int j = std::min(static_cast<int>(y * theta_cells), theta_cells - 1);
        const double t = y * theta_cells - j;
        // Uniform in cos(theta_h) within the cell: constant solid-angle density there.
        const double cos_h =
            cos_theta_nodes_[j] - t * (cos_theta_nodes_[j] - cos_theta_nodes_[j + 1]);
        const double sin_h = std::sqrt(std::max(0.0, 1.0 - cos_h * cos_h));
        const double phi = 2.0 * M_PI * x;
        return Vec3{sin_h * std::cos(phi), sin_h * std::sin(phi), cos_h};
      });
  s.pdf = Pdf(w_o, s.w_i);
  return s;
}

double DBrdf::Pdf(const Vec3& w_o, const Vec3& w_i) const {
  if (w_o.z <= 0) return 0;
  return HalfVectorMixturePdf(w_o, w_i, SpecularProbability(w_o),
                              [&](const Vec3& h) { return HalfVectorPdf(h); });
}

std::string DBrdf::Spec() const {
  const HalfVectorTable& table = params_.p_h;
  std::string spec = "dbrdf:c=" + FormatRgb(params_.c) + ",F0=" + FormatDouble(params_.f0) +
                     ",kd=" + FormatRgb(params_.kd) +
                     ",theta_samples=" + std::to_string(table.theta_samples) +
                     ",phi_samples=" + std::to_string(table.phi_samples) + ",p=";
  for (size_t i = 0; i < table.p.size(); ++i) {
    if (i > 0) spec += ',';
    spec += FormatDouble(table.p[i]);
  }
  return spec;
}

}  // namespace zbrdf
