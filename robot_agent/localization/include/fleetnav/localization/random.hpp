#pragma once

#include <cstdint>

namespace fleetnav::localization {

/// A small, fast pseudo-random generator for particle filters: xoshiro256** (Blackman and
/// Vigna, "Scrambled linear pseudorandom number generators", 2021) seeded through splitmix64,
/// with Box–Muller normals (two per transcendental evaluation). Every filter owns one, seeded by
/// its params, so a run is reproducible for a seed. Not thread-safe; one per thread.
class Rng {
 public:
  explicit Rng(uint64_t seed);

  uint64_t Next();
  /// Uniform in [0, 1).
  double Uniform() { return static_cast<double>(Next() >> 11) * 0x1.0p-53; }
  /// Uniform integer in [0, n); n > 0.
  uint64_t UniformInt(uint64_t n) {
    return static_cast<uint64_t>(Uniform() * static_cast<double>(n));
  }
  /// Standard normal.
  double Normal();

 private:
  uint64_t s_[4];
  double cached_normal_ = 0.0;
  bool has_cached_ = false;
};

/// Quantile of the standard normal distribution (inverse CDF) for p in (0, 1): Acklam's
/// rational approximation refined by one Halley step (relative error below 1e-12).
double NormalQuantile(double p);

}  // namespace fleetnav::localization
