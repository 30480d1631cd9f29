// A seeded random stream whose numbers are the same on every platform and
// standard library (std::uniform_real_distribution and std::normal_distribution
// are implementation-defined, so they are not used).
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <random>

namespace ausbau {

class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}

  // Uniform in [0, 1).
  double Uniform01() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  // Uniform in the open interval (0, 1), as the thesis draws u and range_max.
  double UniformOpen01() {
    double x;
    do x = Uniform01();
    while (x == 0.0);
    return x;
  }
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform01(); }
  // Uniform integer in [0, n).
  std::uint64_t Index(std::uint64_t n) { return static_cast<std::uint64_t>(Uniform01() * n) % n; }
  // Standard normal (Box-Muller, no cached second value).
  double Normal() {
    const double u1 = UniformOpen01(), u2 = Uniform01();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  }
  // Uniformly distributed rotation (Shoemake 1992).
  Eigen::Quaterniond UniformQuaternion() {
    const double u1 = Uniform01(), u2 = 2.0 * M_PI * Uniform01(), u3 = 2.0 * M_PI * Uniform01();
    const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1);
    return Eigen::Quaterniond(b * std::cos(u3), a * std::sin(u2), a * std::cos(u2), b * std::sin(u3));
  }
  std::uint64_t NextSeed() { return engine_(); }

 private:
  std::mt19937_64 engine_;  // the engine itself is fully specified by the standard
};

}  // namespace ausbau
