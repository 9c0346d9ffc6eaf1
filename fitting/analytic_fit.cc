#include "fitting/analytic_fit.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <vector>

#include <ceres/ceres.h>

#include "basis/error.h"
#include "basis/option_checker.h"
#include "basis/parallel.h"
#include "basis/stopwatch.h"
#include "brdf/ashikhmin_shirley.h"
#include "brdf/ggx.h"
#include "brdf/lambertian.h"
#include "brdf/ward.h"
#include "fitting/covariance.h"

namespace zbrdf {
namespace {

// Shape parameter <-> the optimizer's variable u: alpha = exp(u); n = exp(u) - 1.
struct ShapeRange {
  double lo, hi;  // in u
};
ShapeRange Range(AnalyticModel m) {
  if (m == AnalyticModel::kAshikhminShirley) return {std::log(1.0 + 1.0), std::log(1.0 + 1e5)};
  return {std::log(0.005), std::log(2.0)};
}
double ShapeOf(AnalyticModel m, double u) {
  return m == AnalyticModel::kAshikhminShirley ? std::exp(u) - 1.0 : std::exp(u);
}
// d shape / d u.
double ShapeDerivative(double u) { return std::exp(u); }

// The projections of f_r cos(theta_i) below use PairQuadrature::ProjectIsotropicBrdf, which
// projects every channel of a model in one evaluation. Two models that differ only in a
// per-channel parameter (F0 = 0 and F0 = 1) are one evaluation: the parameter's values go in
// separate channels, and each channel is what its model gives.
Eigen::VectorXd ProjectChannel0(const PairQuadrature& q, const Brdf& brdf) {
  return std::move(q.ProjectIsotropicBrdf(brdf)[0]);
}

struct Columns {
  Eigen::VectorXd offset, specular;
};

// O(x) and S(x) for a model at shape x (see the header).
Columns ModelColumns(const PairQuadrature& q, AnalyticModel m, double x) {
  Columns c;
  switch (m) {
    case AnalyticModel::kGgx: {
      // F0 = 0 (channel 0) and F0 = 1 (channel 1) in one evaluation.
      std::array<Eigen::VectorXd, 3> z =
          q.ProjectIsotropicBrdf(GgxBrdf(x, x, Rgb(0.0, 1.0, 0.0), Rgb(0.0)));
      c.offset = std::move(z[0]);
      c.specular = z[1] - c.offset;
      break;
    }
    case AnalyticModel::kWard: {
      c.specular = ProjectChannel0(q, WardBrdf(Rgb(0.0), Rgb(1.0), x, x));
      c.offset = Eigen::VectorXd::Zero(c.specular.size());
      break;
    }
    case AnalyticModel::kAshikhminShirley: {
      // Rs = 0 (channel 0) and Rs = 1 (channel 1) in one evaluation.
      std::array<Eigen::VectorXd, 3> z =
          q.ProjectIsotropicBrdf(AshikhminShirleyBrdf(Rgb(0.0), Rgb(0.0, 1.0, 0.0), x, x));
      c.offset = std::move(z[0]);
      c.specular = z[1] - c.offset;
      break;
    }
  }
  return c;
}

Eigen::VectorXd DiffuseColumn(const PairQuadrature& q, AnalyticModel m) {
  if (m == AnalyticModel::kAshikhminShirley) {
    // Rd (1 - Rs) times the angular factor: the AS model with Rd = 1, Rs = 0 minus its specular
    // part (F = W) at any n.
    // Rd = 1 (channel 0) and Rd = 0 (channel 1) in one evaluation.
    const std::array<Eigen::VectorXd, 3> z =
        q.ProjectIsotropicBrdf(AshikhminShirleyBrdf(Rgb(1.0, 0.0, 0.0), Rgb(0.0), 10.0, 10.0));
    return z[0] - z[1];
  }
  return ProjectChannel0(q, LambertianBrdf(Rgb(1.0)));
}

double SpecularUpperBound(AnalyticModel m) {
  return m == AnalyticModel::kWard ? std::numeric_limits<double>::infinity() : 1.0;
}

// Colours for fixed columns: per channel NNLS on [S, D] against y - O for a - a_min >= 0, with a
// clamped to its upper bound (then b re-solved). Returns chi2.
double SolveAnalyticColours(const FitWeights& w, const Columns& c, const Eigen::VectorXd& diffuse,
                            double a_min, double a_max, Rgb* a, Rgb* b) {
  double chi2 = 0;
  for (int ch = 0; ch < 3; ++ch) {
    const Eigen::VectorXd& wt = w.weight[ch];
    Eigen::MatrixXd m(diffuse.size(), 2);
    m.col(0) = wt.cwiseProduct(c.specular);
    m.col(1) = wt.cwiseProduct(diffuse);
    const Eigen::VectorXd target = wt.cwiseProduct(w.y[ch] - c.offset);
    Eigen::VectorXd x = NonNegativeLeastSquares(m, target - a_min * m.col(0));
    x[0] += a_min;
    if (x[0] > a_max) {
      x[0] = a_max;
      const Eigen::VectorXd rest = target - a_max * m.col(0);
      const double dd = m.col(1).squaredNorm();
      x[1] = dd > 0 ? std::max(0.0, m.col(1).dot(rest) / dd) : 0.0;
    }
    (*a)[ch] = x[0];
    (*b)[ch] = x[1];
    chi2 += (m * x - target).squaredNorm();
  }
  return chi2;
}

class AnalyticCost final : public ceres::CostFunction {
 public:
  AnalyticCost(const PairQuadrature& q, AnalyticModel m, const FitWeights& w,
               const Eigen::VectorXd& diffuse)
      : q_(q), m_(m), w_(w), diffuse_(diffuse) {
    set_num_residuals(3 * static_cast<int>(diffuse.size()));
    mutable_parameter_block_sizes()->assign({1, 3, 3});
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const double u = parameters[0][0];
    const double* a = parameters[1];
    const double* b = parameters[2];
    // Bound the cache here, before any reference into it is taken.
    if (cache_.size() > 64) cache_.clear();
    const Columns& c = At(u);
    const Eigen::Index n = diffuse_.size();
    for (int ch = 0; ch < 3; ++ch) {
      for (Eigen::Index i = 0; i < n; ++i) {
        residuals[ch * n + i] =
            w_.weight[ch][i] * (c.offset[i] + a[ch] * c.specular[i] + b[ch] * diffuse_[i] - w_.y[ch][i]);
      }
    }
    if (!jacobians) return true;
    if (jacobians[0]) {
      // Central difference in u; step ~ cube root of the columns' relative accuracy (1e-6).
      const double h = 1e-3;
      const Columns& plus = At(u + h);
      const Columns& minus = At(u - h);
      for (int ch = 0; ch < 3; ++ch) {
        for (Eigen::Index i = 0; i < n; ++i) {
          const double dp = plus.offset[i] + a[ch] * plus.specular[i];
          const double dm = minus.offset[i] + a[ch] * minus.specular[i];
          jacobians[0][ch * n + i] = w_.weight[ch][i] * (dp - dm) / (2 * h);
        }
      }
    }
    for (int block = 1; block <= 2; ++block) {
      if (!jacobians[block]) continue;
      std::fill(jacobians[block], jacobians[block] + 3 * n * 3, 0.0);
      for (int ch = 0; ch < 3; ++ch) {
        for (Eigen::Index i = 0; i < n; ++i) {
          jacobians[block][(ch * n + i) * 3 + ch] =
              w_.weight[ch][i] * (block == 1 ? c.specular[i] : diffuse_[i]);
        }
      }
    }
    return true;
  }

  const Columns& At(double u) const {
    auto it = cache_.find(u);
    if (it != cache_.end()) return it->second;
    // std::map never moves its elements: references stay valid while entries are added.
    return cache_.emplace(u, ModelColumns(q_, m_, ShapeOf(m_, u))).first->second;
  }

 private:
  const PairQuadrature& q_;
  AnalyticModel m_;
  const FitWeights& w_;
  const Eigen::VectorXd& diffuse_;
  mutable std::map<double, Columns> cache_;
};

std::shared_ptr<const Brdf> MakeModel(AnalyticModel m, double x, const Rgb& a, const Rgb& b,
                                      std::vector<std::string>* conditions) {
  switch (m) {
    case AnalyticModel::kGgx:
      return std::make_shared<GgxBrdf>(x, x, a, b);
    case AnalyticModel::kWard:
      return std::make_shared<WardBrdf>(b, a, x, x);
    case AnalyticModel::kAshikhminShirley: {
      Rgb rd;
      for (int ch = 0; ch < 3; ++ch) {
        if (a[ch] < 1.0 - 1e-9) {
          rd[ch] = b[ch] / (1.0 - a[ch]);
        } else if (b[ch] > 0) {
          if (conditions) conditions->push_back("Rs reached 1: the diffuse term vanishes there");
        }
      }
      return std::make_shared<AshikhminShirleyBrdf>(rd, a, x, x);
    }
  }
  return nullptr;
}

}  // namespace

std::string AnalyticModelName(AnalyticModel model) {
  switch (model) {
    case AnalyticModel::kGgx: return "ggx";
    case AnalyticModel::kWard: return "ward";
    case AnalyticModel::kAshikhminShirley: return "as";
  }
  return "?";
}

AnalyticModel ParseAnalyticModel(const std::string& name) {
  for (AnalyticModel m : {AnalyticModel::kGgx, AnalyticModel::kWard, AnalyticModel::kAshikhminShirley}) {
    if (AnalyticModelName(m) == name) return m;
  }
  throw InputError("unknown analytic model '" + name + "'; use ggx, ward or as");
}

nlohmann::json AnalyticFitResult::ToJson() const {
  auto rgb = [](const Rgb& c) { return nlohmann::json::array({c.r, c.g, c.b}); };
  auto finite = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
  auto frgb = [&](const Rgb& c) { return nlohmann::json::array({finite(c.r), finite(c.g), finite(c.b)}); };
  const char* shape_key = model == AnalyticModel::kAshikhminShirley ? "n" : "alpha";
  const char* spec_key = model == AnalyticModel::kGgx ? "F0" : (model == AnalyticModel::kWard ? "rho_s" : "Rs");
  const char* diff_key = model == AnalyticModel::kGgx ? "kd" : (model == AnalyticModel::kWard ? "rho_d" : "Rd");
  nlohmann::json j;
  j[shape_key] = shape;
  j[spec_key] = rgb(specular);
  j[diff_key] = rgb(diffuse);
  nlohmann::json u;
  u["available"] = uncertainty.available;
  u[shape_key] = finite(uncertainty.shape);
  u[spec_key] = frgb(uncertainty.specular);
  u[diff_key] = frgb(uncertainty.diffuse);
  j["uncertainty"] = u;
  j["isotropy"] = {{"isotropic", isotropy.isotropic},
                   {"anisotropic_energy_fraction", isotropy.anisotropic_energy_fraction},
                   {"chi2_per_dof", isotropy.chi2_per_dof}};
  return j;
}

void AnalyticFitOptions::Validate() const {
  OptionChecker check("AnalyticFitOptions");
  check.AtLeast("max_iterations", max_iterations, 1)
      .InRangeBelow("f0_min", f0_min, 0, 1)
      .Nested("quadrature", quadrature)
      .ThrowIfInvalid();
}

namespace {

// The options, validated before the fitter's members are built from them.
const AnalyticFitOptions& Validated(const AnalyticFitOptions& options) {
  options.Validate();
  return options;
}

}  // namespace

AnalyticFitter::AnalyticFitter(const Zone& zone, int order, const AnalyticFitOptions& options)
    : zone_(zone),
      order_(order),
      options_(Validated(options)),
      quadrature_(zone, order, options.quadrature) {}

AnalyticFitResult AnalyticFitter::Fit(const ZonalTensor& data, AnalyticModel model) const {
  const auto t_start = WallClock::now();
  if (data.order != order_ || !(data.zone() == zone_)) {
    throw InputError("analytic fit: the data (zone " + data.zone().ToString() + ", order " +
                     std::to_string(data.order) + ") do not match the fitter's (zone " +
                     zone_.ToString() + ", order " + std::to_string(order_) + ")");
  }
  AnalyticFitResult result;
  result.model = model;
  result.isotropy = AnalyzeIsotropy(data);
  const IsotropicData iso = IsotropicCoefficients(data);
  const FitWeights w = MakeFitWeights(iso.z, iso.variance);
  result.conditions = w.conditions;
  if (!result.isotropy.isotropic) {
    result.conditions.push_back(
        "the data are anisotropic; the isotropic " + AnalyticModelName(model) +
        " model was fitted to their azimuthal average (use --model dbrdf for a 2-D fit)");
  }
  const double a_max = SpecularUpperBound(model);
  const double a_min = model == AnalyticModel::kWard ? 0.0 : options_.f0_min;
  if (!w.any_signal) {
    // No model of these families is black (Schlick's F never vanishes at grazing angles), so
    // degenerate data give a black Lambertian.
    result.brdf = std::make_shared<LambertianBrdf>(Rgb(0.0));
    result.spec = result.brdf->Spec();
    result.conditions.push_back("nothing was fitted; the model is black (" + result.spec + ")");
    result.total_seconds = SecondsSince(t_start);
    return result;
  }
  const auto t_pre = WallClock::now();
  const Eigen::VectorXd diffuse = DiffuseColumn(quadrature_, model);
  result.precompute_seconds = SecondsSince(t_pre);
  const auto t_solve = WallClock::now();
  // Variable projection scan over the shape.
  const ShapeRange range = Range(model);
  const double u0 = MinimizeScalar(
      [&](double u) {
        Rgb a, b;
        return SolveAnalyticColours(w, ModelColumns(quadrature_, model, ShapeOf(model, u)), diffuse,
                                    a_min, a_max, &a, &b);
      },
      range.lo, range.hi, 16, 18);
  Rgb a0, b0;
  SolveAnalyticColours(w, ModelColumns(quadrature_, model, ShapeOf(model, u0)), diffuse, a_min,
                       a_max, &a0, &b0);
  // Ceres refinement.
  double u = u0;
  double a[3] = {a0.r, a0.g, a0.b}, b[3] = {b0.r, b0.g, b0.b};
  // Start strictly inside the bounds.
  for (int ch = 0; ch < 3; ++ch) {
    if (std::isfinite(a_max)) a[ch] = std::min(a[ch], a_max * (1 - 1e-6));
    if (a_min > 0) a[ch] = std::max(a[ch], a_min * (1 + 1e-6));
  }
  ceres::Problem problem;
  auto* cost = new AnalyticCost(quadrature_, model, w, diffuse);
  problem.AddResidualBlock(cost, nullptr, &u, a, b);
  problem.SetParameterLowerBound(&u, 0, range.lo);
  problem.SetParameterUpperBound(&u, 0, range.hi);
  for (int ch = 0; ch < 3; ++ch) {
    problem.SetParameterLowerBound(a, ch, a_min);
    if (std::isfinite(a_max)) problem.SetParameterUpperBound(a, ch, a_max);
    problem.SetParameterLowerBound(b, ch, 0.0);
  }
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_QR;
  solver.max_num_iterations = options_.max_iterations;
  solver.function_tolerance = 1e-9;
  solver.parameter_tolerance = 1e-9;
  solver.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);
  result.shape = ShapeOf(model, u);
  result.specular = {a[0], a[1], a[2]};
  result.diffuse = {b[0], b[1], b[2]};
  const Columns& c = cost->At(u);
  std::array<Eigen::VectorXd, 3> prediction;
  for (int ch = 0; ch < 3; ++ch) prediction[ch] = c.offset + a[ch] * c.specular + b[ch] * diffuse;
  result.statistics = ComputeFitStatistics(w, prediction, 7);
  result.statistics.iterations = static_cast<int>(summary.iterations.size());
  result.statistics.termination = summary.message;
  if (options_.covariance) {
    const auto sd = ParameterStandardDeviations(problem, {{&u, 1}, {a, 3}, {b, 3}},
                                                result.statistics.chi2_per_dof);
    if (sd) {
      result.uncertainty.available = true;
      result.uncertainty.shape = ShapeDerivative(u) * (*sd)[0][0];
      for (int ch = 0; ch < 3; ++ch) {
        result.uncertainty.specular[ch] = (*sd)[1][ch];
        result.uncertainty.diffuse[ch] = (*sd)[2][ch];
      }
    } else {
      result.conditions.push_back(kUncertaintiesUnavailable);
    }
  }
  // The diffuse parameter as the model takes it (AS: Rd from Rd (1 - Rs)).
  result.brdf = MakeModel(model, result.shape, result.specular, result.diffuse, &result.conditions);
  if (model == AnalyticModel::kAshikhminShirley) {
    result.diffuse = static_cast<const AshikhminShirleyBrdf&>(*result.brdf).rd();
  }
  result.spec = result.brdf->Spec();
  result.fitted = true;
  if (result.specular.Max() <= 0) {
    result.conditions.push_back("no specular reflection detected: the lobe shape is undetermined");
  }
  const double u_margin = 1e-3;
  if (result.specular.Max() > 0 && (u <= range.lo + u_margin || u >= range.hi - u_margin)) {
    result.conditions.push_back("the lobe shape reached the end of its range (" +
                                std::to_string(result.shape) + "): the data want a sharper or "
                                "broader lobe than the model allows");
  }
  if (result.statistics.chi2_per_dof > 25) {
    char text[200];
    std::snprintf(text, sizeof(text),
                  "the %s model does not explain the data within their noise (chi2/dof = %.3g, "
                  "relative residual %.2g%%)",
                  AnalyticModelName(model).c_str(), result.statistics.chi2_per_dof,
                  100 * result.statistics.relative_residual);
    result.conditions.push_back(text);
  }
  result.solve_seconds = SecondsSince(t_solve);
  result.total_seconds = SecondsSince(t_start);
  return result;
}

}  // namespace zbrdf
