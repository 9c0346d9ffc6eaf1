// Shared by the basis tests: fixed-seed random coefficient vectors.
#pragma once

#include <cstdint>
#include <random>

#include <Eigen/Dense>

namespace zbrdf::testing {

// n independent standard normal values from a fixed seed.
inline Eigen::VectorXd RandomCoefficients(int n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0, 1);
  Eigen::VectorXd y(n);
  for (int i = 0; i < n; ++i) y(i) = normal(rng);
  return y;
}

}  // namespace zbrdf::testing
