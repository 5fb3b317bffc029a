// Standard optimisation test functions (global minimum 0 at the origin for Sphere, Rastrigin and
// Ackley; at (1, ..., 1) for Rosenbrock), shared by cuckoo_search_test and its benchmark.
#pragma once

#include <cmath>
#include <cstddef>
#include <numbers>
#include <span>

namespace gyrocomp::test_functions {

inline double Sphere(std::span<const double> x) {
  double s = 0.0;
  for (double v : x) s += v * v;
  return s;
}

inline double Rosenbrock(std::span<const double> x) {
  double s = 0.0;
  for (std::size_t i = 0; i + 1 < x.size(); ++i)
    s += 100.0 * std::pow(x[i + 1] - x[i] * x[i], 2) + std::pow(1.0 - x[i], 2);
  return s;
}

inline double Rastrigin(std::span<const double> x) {
  double s = 10.0 * static_cast<double>(x.size());
  for (double v : x) s += v * v - 10.0 * std::cos(2.0 * std::numbers::pi * v);
  return s;
}

inline double Ackley(std::span<const double> x) {
  const double n = static_cast<double>(x.size());
  double s1 = 0.0, s2 = 0.0;
  for (double v : x) {
    s1 += v * v;
    s2 += std::cos(2.0 * std::numbers::pi * v);
  }
  return -20.0 * std::exp(-0.2 * std::sqrt(s1 / n)) - std::exp(s2 / n) + 20.0 + std::numbers::e;
}

}  // namespace gyrocomp::test_functions
