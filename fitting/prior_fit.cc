#include "fitting/prior_fit.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <random>
#include <set>
#include <span>

#include "basis/error.h"
#include "basis/option_checker.h"
#include "basis/parallel.h"

namespace zbrdf {
namespace {

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// Cosine-weighted measure of each node (for summaries): the node's share of
// integral integral (.) cos^2(theta_i) dw_i dw_o with dw_i dw_o = 4 cos(theta_d) dw_h dw_d
// (Rusinkiewicz 1998), theta_h = (pi/2) u^2, trapezoid weights in (u, theta_d, phi_d).
std::vector<double> NodeMeasure(const HalfDiffGrid& g, const Zone* zone_only) {
  std::vector<double> w(g.size(), 0.0);
  auto trap = [](int i, int n) { return (i == 0 || i == n - 1) ? 0.5 : 1.0; };
  for (int ih = 0; ih < g.theta_h_nodes(); ++ih) {
    const double u = static_cast<double>(ih) / (g.theta_h_nodes() - 1);
    const double dth = M_PI * u / (g.theta_h_nodes() - 1) * trap(ih, g.theta_h_nodes());
    for (int id = 0; id < g.theta_d_nodes(); ++id) {
      const double dtd = 0.5 * M_PI / (g.theta_d_nodes() - 1) * trap(id, g.theta_d_nodes());
      for (int ip = 0; ip < g.phi_d_nodes(); ++ip) {
        const int n = g.Index(ih, id, ip);
        Vec3 wi, wo;
        g.Directions(n, &wi, &wo);
        if (wi.z <= 0 || wo.z <= 0) continue;
        if (zone_only && !(zone_only->ContainsCosTheta(wi.z) && zone_only->ContainsCosTheta(wo.z))) {
          continue;
        }
        const double dpd = 0.5 * M_PI / (g.phi_d_nodes() - 1) * trap(ip, g.phi_d_nodes());
        w[n] = 4.0 * std::cos(g.ThetaDiff(id)) * std::sin(g.ThetaHalf(ih)) *
               std::sin(g.ThetaDiff(id)) * dth * dtd * dpd * wi.z * wi.z;
      }
    }
  }
  return w;
}

}  // namespace

void PriorFitOptions::Validate() const {
  OptionChecker check("PriorFitOptions");
  check.InRange("model_error_floor", model_error_floor, 0.0, 1.0)
      .InRange("replicates", replicates, 0, 256)
      .InRange("replicate_atom_fraction", replicate_atom_fraction, 0.05, 1.0)
      .InRange("pca_components", pca_components, 0, 200)
      .InRange("pca_ridge", pca_ridge, 1e-6, 1e6)
      .InRange("pca_epsilon", pca_epsilon, 1e-9, 1.0)
      .InRange("pca_weight", pca_weight, 0.0, 1.0)
      .ThrowIfInvalid();
  projection.Validate();
}

Eigen::VectorXd NonNegativeLeastSquaresGram(const Eigen::MatrixXd& m, const Eigen::VectorXd& v) {
  const int n = static_cast<int>(v.size());
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  if (n == 0) return x;
  const double ridge = 1e-12 * m.trace() / n;
  const double tol = 1e-13 * std::max(1.0, v.cwiseAbs().maxCoeff());
  std::vector<char> passive(n, 0);
  auto solve = [&](const std::vector<int>& p) {
    Eigen::MatrixXd mp(p.size(), p.size());
    Eigen::VectorXd vp(p.size());
    for (size_t a = 0; a < p.size(); ++a) {
      vp[a] = v[p[a]];
      for (size_t b = 0; b < p.size(); ++b) mp(a, b) = m(p[a], p[b]);
      mp(a, a) += ridge;
    }
    return Eigen::VectorXd(mp.ldlt().solve(vp));
  };
  for (int outer = 0; outer < 3 * n + 3; ++outer) {
    const Eigen::VectorXd gradient = v - m * x;
    int best = -1;
    double best_g = tol;
    for (int j = 0; j < n; ++j) {
      if (!passive[j] && gradient[j] > best_g) {
        best_g = gradient[j];
        best = j;
      }
    }
    if (best < 0) break;
    passive[best] = 1;
    for (int inner = 0; inner < 3 * n + 3; ++inner) {
      std::vector<int> p;
      for (int j = 0; j < n; ++j) {
        if (passive[j]) p.push_back(j);
      }
      const Eigen::VectorXd zp = solve(p);
      bool feasible = true;
      for (size_t k = 0; k < p.size(); ++k) feasible = feasible && zp[k] > 0;
      if (feasible) {
        x.setZero();
        for (size_t k = 0; k < p.size(); ++k) x[p[k]] = zp[k];
        break;
      }
      double step = 1.0;
      for (size_t k = 0; k < p.size(); ++k) {
        if (zp[k] <= 0) step = std::min(step, x[p[k]] / (x[p[k]] - zp[k]));
      }
      for (size_t k = 0; k < p.size(); ++k) x[p[k]] += step * (zp[k] - x[p[k]]);
      const double small = 1e-15 * std::max(1.0, x.cwiseAbs().maxCoeff());
      for (int j : p) {
        if (x[j] <= small) {
          x[j] = 0;
          passive[j] = 0;
        }
      }
      // A degenerate step that frees the entering column again would loop; stop with it out.
      if (!passive[best]) break;
    }
  }
  return x;
}

PriorFitter::PriorFitter(const Zone& zone, int order, std::shared_ptr<const BrdfPrior> prior,
                         const PriorFitOptions& options, const Eigen::MatrixXf* table_projection)
    : zone_(zone), order_(order), prior_(std::move(prior)), options_(options) {
  options.Validate();
  if (!prior_) throw InputError("prior fit: no prior given");
  const auto start = std::chrono::steady_clock::now();
  const HalfDiffGrid& grid = prior_->grid;
  const int atoms = static_cast<int>(prior_->atoms.cols());
  const int rows = IsotropicLayout(order).size();
  if (table_projection) {
    if (table_projection->rows() != rows || table_projection->cols() != grid.size()) {
      throw InputError("prior fit: a cached table projection of " +
                       std::to_string(table_projection->rows()) + " x " +
                       std::to_string(table_projection->cols()) + " does not fit order " +
                       std::to_string(order) + " and a " + grid.ToString() + " grid");
    }
    table_projection_ = *table_projection;
  } else {
    const PeakProjector projector(zone, order, options.projection);
    table_projection_ =
        projector
            .Matrix(
                [&grid](const Vec3& wi, const Vec3& wr, int* cols, double* weights) {
                  if (wi.z <= 0 || wr.z <= 0) return 0;
                  const HalfDiffGrid::Stencil s = grid.StencilOf(HalfDiffOf(wi, wr));
                  for (int k = 0; k < 8; ++k) {
                    cols[k] = s.index[k];
                    weights[k] = s.weight[k];
                  }
                  return 8;
                },
                grid.size())
            .cast<float>();
  }
  projection_.resize(rows, atoms + 1);
  projection_.leftCols(atoms) = (table_projection_ * prior_->atoms).cast<double>();
  projection_.col(atoms) =
      table_projection_.cast<double>() * Eigen::VectorXd::Constant(grid.size(), 1.0 / M_PI);
  log_weight_.resize(grid.size());
  for (int n = 0; n < grid.size(); ++n) {
    Vec3 wi, wo;
    grid.Directions(n, &wi, &wo);
    log_weight_[n] = std::max(std::max(0.0, wi.z) * std::max(0.0, wo.z), 1e-3);
    if (wi.z > 0 && wo.z > 0 && zone.ContainsCosTheta(wi.z) && zone.ContainsCosTheta(wo.z)) {
      zone_nodes_.push_back(n);
    }
  }
  precompute_seconds_ = Seconds(start);
}

std::shared_ptr<const PriorFitter::LogPca> PriorFitter::Pca(
    const std::vector<std::string>& excluded, const PriorFitOptions& options) const {
  std::lock_guard<std::mutex> lock(pca_mutex_);
  if (pca_ && pca_->excluded == excluded && pca_->components == options.pca_components &&
      pca_->epsilon == options.pca_epsilon) {
    return pca_;
  }
  const BrdfPrior& prior = *prior_;
  const int cells = prior.grid.size();
  std::vector<int> columns;
  for (int a = 0; a < static_cast<int>(prior.atoms.cols()); ++a) {
    if (std::find(excluded.begin(), excluded.end(), prior.materials[a / 3]) == excluded.end()) {
      columns.push_back(a);
    }
  }
  const int samples = static_cast<int>(columns.size());
  auto pca = std::make_shared<LogPca>();
  pca->excluded = excluded;
  pca->epsilon = options.pca_epsilon;
  pca->components = std::min(options.pca_components, samples - 1);
  if (pca->components <= 0) return pca_ = pca;
  Eigen::MatrixXd y(samples, cells);
  for (int k = 0; k < samples; ++k) {
    for (int n = 0; n < cells; ++n) {
      y(k, n) = std::log(prior.atoms(n, columns[k]) * log_weight_[n] + options.pca_epsilon);
    }
  }
  pca->mean = y.colwise().mean().transpose();
  y.rowwise() -= pca->mean.transpose();
  // Principal components from the samples' Gram matrix (samples << nodes).
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(y * y.transpose());
  const int k_count = pca->components;
  pca->basis.resize(cells, k_count);
  pca->sigma.resize(k_count);
  for (int k = 0; k < k_count; ++k) {
    const int e = samples - 1 - k;  // eigenvalues ascending
    const double lambda = std::max(eigen.eigenvalues()[e], 1e-300);
    pca->basis.col(k) = y.transpose() * eigen.eigenvectors().col(e) / std::sqrt(lambda);
    pca->sigma[k] = std::sqrt(lambda / samples);
  }
  return pca_ = pca;
}

void PriorFitter::Extrapolate(const LogPca& pca, double ridge, double weight,
                              std::vector<double>* table) const {
  if (pca.components <= 0 || zone_nodes_.empty() || table->empty()) return;
  if (std::all_of(table->begin(), table->end(), [](double v) { return v <= 0; })) return;
  const int k_count = pca.components, zone_count = static_cast<int>(zone_nodes_.size());
  Eigen::MatrixXd a(zone_count, k_count);
  Eigen::VectorXd r(zone_count);
  for (int i = 0; i < zone_count; ++i) {
    const int n = zone_nodes_[i];
    a.row(i) = pca.basis.row(n);
    r[i] = std::log(std::max(0.0, (*table)[n]) * log_weight_[n] + pca.epsilon) - pca.mean[n];
  }
  Eigen::MatrixXd normal = a.transpose() * a;
  for (int k = 0; k < k_count; ++k) normal(k, k) += ridge / (pca.sigma[k] * pca.sigma[k]);
  const Eigen::VectorXd w = normal.ldlt().solve(a.transpose() * r);
  const Eigen::VectorXd y = pca.mean + pca.basis * w;
  const double w_pca = weight;
  for (size_t n = 0; n < table->size(); ++n) {
    const double extrapolated = std::max(0.0, std::exp(y[n]) - pca.epsilon) / log_weight_[n];
    (*table)[n] = w_pca * extrapolated + (1.0 - w_pca) * (*table)[n];
  }
  FillBelowHorizon(prior_->grid, std::span<double>(*table));
}

PriorFitResult PriorFitter::Fit(const ZonalTensor& data) const { return Fit(data, options_); }

PriorFitResult PriorFitter::Fit(const ZonalTensor& data, const PriorFitOptions& options) const {
  options.Validate();
  const auto start = std::chrono::steady_clock::now();
  if (data.order != order_ || !(data.zone() == zone_)) {
    throw InputError("prior fit: the data's zone " + data.zone().ToString() + " and order " +
                     std::to_string(data.order) + " differ from the fitter's " +
                     zone_.ToString() + ", order " + std::to_string(order_));
  }
  if (const std::string problems = data.Problems(); !problems.empty()) {
    throw InputError("prior fit: " + problems);
  }
  PriorFitResult result;
  result.precompute_seconds = precompute_seconds_;
  const BrdfPrior& prior = *prior_;
  const HalfDiffGrid& grid = prior.grid;
  const int atoms = static_cast<int>(prior.atoms.cols());

  // The columns in play.
  std::set<std::string> excluded;
  for (const std::string& name : options.exclude) {
    if (prior.MaterialIndex(name) >= 0) excluded.insert(name);
  }
  result.excluded.assign(excluded.begin(), excluded.end());
  std::vector<int> columns;
  for (int a = 0; a < atoms; ++a) {
    if (!excluded.count(prior.materials[a / 3])) columns.push_back(a);
  }
  if (options.lambertian_atom) columns.push_back(atoms);
  result.atoms_available = static_cast<int>(columns.size());
  if (columns.empty()) {
    result.conditions.push_back("every material of the prior was excluded; nothing to fit");
    result.brdf = std::make_shared<TabulatedBrdf>(grid, std::vector<Rgb>(grid.size()),
                                                  std::vector<Rgb>(), "prior-fit");
    return result;
  }
  auto column_table = [&prior, atoms](int col, int node) {
    return col == atoms ? 1.0 / M_PI : static_cast<double>(prior.atoms(node, col));
  };

  const IsotropyReport isotropy = AnalyzeIsotropy(data);
  if (!isotropy.isotropic) {
    result.conditions.push_back(
        "the data are anisotropic (" +
        std::to_string(100.0 * isotropy.anisotropic_energy_fraction) +
        "% of the energy off the isotropic blocks); the prior is isotropic and fits their "
        "azimuthal average");
  }
  const IsotropicData iso = IsotropicCoefficients(data);
  const int rows = iso.layout.size();

  std::array<Eigen::VectorXd, 3> y, variance, model;
  std::array<Eigen::VectorXd, 3> weights_main;
  std::array<std::vector<double>, 3> tables_main;
  std::vector<std::array<std::vector<double>, 3>> tables_rep(options.replicates);
  bool any = false;
  for (int c = 0; c < 3; ++c) {
    y[c] = iso.z[c];
    variance[c] = iso.variance[c];
    Eigen::VectorXd w(rows);
    double sum2 = 0;
    int finite = 0;
    for (int i = 0; i < rows; ++i) {
      if (std::isfinite(y[c][i]) && std::isfinite(variance[c][i])) {
        sum2 += y[c][i] * y[c][i];
        ++finite;
      }
    }
    const double rms = finite > 0 ? std::sqrt(sum2 / finite) : 0.0;
    const double floor2 = std::pow(options.model_error_floor * rms, 2);
    for (int i = 0; i < rows; ++i) {
      const double s2 = variance[c][i] + floor2;
      const bool ok = std::isfinite(y[c][i]) && std::isfinite(variance[c][i]) && s2 > 0;
      w[i] = ok ? 1.0 / std::sqrt(s2) : 0.0;
      variance[c][i] = ok ? s2 : std::numeric_limits<double>::infinity();
      if (!ok) y[c][i] = 0.0;
    }
    tables_main[c].assign(grid.size(), 0.0);
    model[c] = Eigen::VectorXd::Zero(rows);
    if (!(rms > 0)) continue;
    any = true;
    // Whitened, column-normalized design.
    Eigen::MatrixXd b(rows, columns.size());
    Eigen::VectorXd norms(columns.size());
    for (size_t k = 0; k < columns.size(); ++k) {
      b.col(k) = projection_.col(columns[k]).cwiseProduct(w);
      norms[k] = b.col(k).norm();
      if (norms[k] > 0) b.col(k) /= norms[k];
    }
    const Eigen::MatrixXd gram = b.transpose() * b;
    const Eigen::VectorXd yw = y[c].cwiseProduct(w);
    auto solve = [&](const std::vector<int>& subset, const Eigen::VectorXd& target) {
      Eigen::MatrixXd m(subset.size(), subset.size());
      Eigen::VectorXd v(subset.size());
      for (size_t a = 0; a < subset.size(); ++a) {
        v[a] = b.col(subset[a]).dot(target);
        for (size_t bb = 0; bb < subset.size(); ++bb) m(a, bb) = gram(subset[a], subset[bb]);
      }
      const Eigen::VectorXd x = NonNegativeLeastSquaresGram(m, v);
      Eigen::VectorXd full = Eigen::VectorXd::Zero(columns.size());
      for (size_t a = 0; a < subset.size(); ++a) {
        if (norms[subset[a]] > 0) full[subset[a]] = x[a] / norms[subset[a]];
      }
      return full;
    };
    auto table_of = [&](const Eigen::VectorXd& a, std::vector<double>* out) {
      out->assign(grid.size(), 0.0);
      for (size_t k = 0; k < columns.size(); ++k) {
        if (a[k] <= 0) continue;
        for (int n = 0; n < grid.size(); ++n) (*out)[n] += a[k] * column_table(columns[k], n);
      }
    };
    std::vector<int> all(columns.size());
    std::iota(all.begin(), all.end(), 0);
    const Eigen::VectorXd a = solve(all, yw);
    table_of(a, &tables_main[c]);
    for (size_t k = 0; k < columns.size(); ++k) model[c] += a[k] * projection_.col(columns[k]);
    // Contributions.
    double total = 0;
    for (size_t k = 0; k < columns.size(); ++k) total += a[k] * norms[k];
    for (size_t k = 0; k < columns.size(); ++k) {
      if (a[k] <= 0) continue;
      PriorFitResult::Contribution contribution;
      contribution.material = columns[k] == atoms ? "lambertian" : prior.materials[columns[k] / 3];
      contribution.channel = columns[k] == atoms ? c : columns[k] % 3;
      contribution.share = a[k] * norms[k] / total;
      result.contributions[c].push_back(contribution);
    }
    std::sort(result.contributions[c].begin(), result.contributions[c].end(),
              [](const auto& p, const auto& q) { return p.share > q.share; });
    result.atoms_used += static_cast<int>(result.contributions[c].size());
    // Replicates: half the atoms and the data perturbed by their sigma (fixed seeds per
    // replicate and channel, so results do not depend on the thread count).
    ParallelFor(options.replicates, 1, [&](int64_t r0, int64_t r1) {
      for (int64_t r = r0; r < r1; ++r) {
        std::mt19937_64 rng(options.seed * 1000003ull + static_cast<uint64_t>(r) * 7919ull + c);
        std::uniform_real_distribution<double> uniform(0.0, 1.0);
        std::normal_distribution<double> normal(0.0, 1.0);
        std::vector<int> subset;
        for (size_t k = 0; k < columns.size(); ++k) {
          if (uniform(rng) < options.replicate_atom_fraction) subset.push_back(static_cast<int>(k));
        }
        Eigen::VectorXd target = yw;
        for (int i = 0; i < rows; ++i) {
          if (w[i] > 0) target[i] += normal(rng);  // whitened: unit variance
        }
        table_of(solve(subset, target), &tables_rep[r][c]);
      }
    });
  }
  if (!any) result.conditions.push_back("every channel's coefficients are zero; nothing to fit");
  if (any && options.pca_components > 0) {
    const std::shared_ptr<const LogPca> pca = Pca(result.excluded, options);
    ParallelFor(3 * (options.replicates + 1), 1, [&](int64_t i0, int64_t i1) {
      for (int64_t i = i0; i < i1; ++i) {
        const int c = static_cast<int>(i % 3), r = static_cast<int>(i / 3) - 1;
        Extrapolate(*pca, options.pca_ridge, options.pca_weight,
                    r < 0 ? &tables_main[c] : &tables_rep[r][c]);
      }
    });
    for (int c = 0; c < 3; ++c) {
      Eigen::VectorXf t(grid.size());
      for (int n = 0; n < grid.size(); ++n) t[n] = static_cast<float>(tables_main[c][n]);
      model[c] = (table_projection_ * t).cast<double>();
    }
  }

  std::vector<Rgb> values(grid.size()), sigma;
  for (int n = 0; n < grid.size(); ++n) {
    values[n] = {tables_main[0][n], tables_main[1][n], tables_main[2][n]};
  }
  if (options.replicates > 1 && any) {
    sigma.assign(grid.size(), Rgb());
    for (int n = 0; n < grid.size(); ++n) {
      for (int c = 0; c < 3; ++c) {
        double mean = 0, m2 = 0;
        for (int r = 0; r < options.replicates; ++r) mean += tables_rep[r][c][n];
        mean /= options.replicates;
        for (int r = 0; r < options.replicates; ++r) m2 += std::pow(tables_rep[r][c][n] - mean, 2);
        sigma[n][c] = std::sqrt(m2 / (options.replicates - 1));
      }
    }
  }
  result.brdf = std::make_shared<TabulatedBrdf>(grid, std::move(values), std::move(sigma),
                                                "prior-fit");
  result.fitted = any;
  result.pca_components = any ? options.pca_components : 0;
  const FitWeights fw = MakeFitWeights(y, variance);
  result.statistics = ComputeFitStatistics(fw, model, result.atoms_used);
  result.model = model;
  result.statistics.termination = "non-negative least squares converged";
  if (!result.brdf->sigma().empty()) {
    for (const Zone* z : {static_cast<const Zone*>(nullptr), &zone_}) {
      const std::vector<double> measure = NodeMeasure(grid, z);
      double s2 = 0, v2 = 0;
      for (int n = 0; n < grid.size(); ++n) {
        for (int c = 0; c < 3; ++c) {
          s2 += measure[n] * std::pow(result.brdf->sigma()[n][c], 2);
          v2 += measure[n] * std::pow(result.brdf->values()[n][c], 2);
        }
      }
      (z ? result.relative_uncertainty_zone : result.relative_uncertainty_hemisphere) =
          v2 > 0 ? std::sqrt(s2 / v2) : 0.0;
    }
  }
  result.total_seconds = Seconds(start) + precompute_seconds_;
  result.solve_seconds = Seconds(start);
  return result;
}

nlohmann::json PriorFitResult::ToJson() const {
  nlohmann::json j;
  j["fitted"] = fitted;
  j["atoms_available"] = atoms_available;
  j["atoms_used"] = atoms_used;
  j["excluded"] = excluded;
  j["relative_uncertainty_hemisphere"] = relative_uncertainty_hemisphere;
  j["relative_uncertainty_zone"] = relative_uncertainty_zone;
  j["pca_components"] = pca_components;
  nlohmann::json contrib = nlohmann::json::object();
  for (int c = 0; c < 3; ++c) {
    nlohmann::json list = nlohmann::json::array();
    for (size_t k = 0; k < contributions[c].size() && k < 8; ++k) {
      list.push_back({{"material", contributions[c][k].material},
                      {"channel", kRgbChannelNames[contributions[c][k].channel]},
                      {"share", contributions[c][k].share}});
    }
    contrib[kRgbChannelNames[c]] = list;
  }
  j["contributions"] = contrib;
  j["statistics"] = {{"chi2", statistics.chi2},
                     {"chi2_per_dof", statistics.chi2_per_dof},
                     {"relative_residual", statistics.relative_residual},
                     {"residuals", statistics.residuals},
                     {"parameters", statistics.parameters}};
  j["conditions"] = conditions;
  j["time_s"] = {{"precompute", precompute_seconds}, {"solve", solve_seconds}, {"total", total_seconds}};
  return j;
}

}  // namespace zbrdf
