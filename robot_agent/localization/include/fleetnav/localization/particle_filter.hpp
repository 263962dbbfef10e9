#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "absl/status/status.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/localization/random.hpp"

namespace fleetnav::localization {

/// Particles as a structure of arrays: positions and yaw in float (sub-micrometre on a 100 m
/// map), normalised weights in double, and a float scratch array for the log-likelihood of the
/// current update. Resampling writes into the `next_*` buffers and swaps, so it never
/// allocates once the set has reached its largest size. Value type; not thread-safe.
struct ParticleSet {
  std::vector<float> x_m, y_m, yaw_rad;
  std::vector<double> weight;
  std::vector<float> log_likelihood;
  std::vector<float> next_x_m, next_y_m, next_yaw_rad;

  size_t size() const { return x_m.size(); }
  void Resize(size_t n);
  /// Reserves room (including resampling buffers) for n particles.
  void Reserve(size_t n);
  void SetUniformWeights();
  /// Bytes held per particle, counting every array above.
  static constexpr size_t kBytesPerParticle =
      3 * sizeof(float) + sizeof(double) + sizeof(float) + 3 * sizeof(float);
};

/// The number of samples KLD-sampling asks for (Fox 2003, eq. 12): for k occupied bins,
/// n = (k−1)/(2ε)·(1 − 2/(9(k−1)) + sqrt(2/(9(k−1)))·z_{1−δ})³ with z_{1−δ} the standard-normal
/// quantile of 1 − δ (not the probability, a known fault of ROS amcl's pf_resample_limit).
size_t KldSampleCount(size_t occupied_bins, double epsilon, double delta);

/// Effective sample size 1/Σw² of normalised weights.
double EffectiveSampleSize(const std::vector<double>& weight);

/// Systematic (low-variance) resampling, Probabilistic Robotics Table 4.4: one uniform draw and
/// a single O(N + M) sweep over the cumulative weights. Returns the `count` chosen indices into
/// `indices` (sorted ascending). Weights need not be normalised but must be ≥ 0 with a positive
/// sum.
void SystematicResample(const std::vector<double>& weight, size_t count, Rng& rng,
                        std::vector<uint32_t>& indices);

/// Spatial histogram of particles for KLD-sampling and clustering: bins of bin_xy_m × bin_xy_m ×
/// bin_yaw_rad. Counting is O(N) with a flat hash set.
size_t CountOccupiedBins(const ParticleSet& particles, double bin_xy_m, double bin_yaw_rad);

/// A weighted pose estimate: mean (circular in yaw), 3×3 covariance, the weight it carries.
struct ClusterEstimate {
  Pose2 mean;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  double weight = 0.0;
  size_t particle_count = 0;
};

/// Groups particles into clusters of face- or corner-adjacent occupied bins (bin_xy_m,
/// bin_yaw_rad; yaw wraps) and returns the clusters sorted by total weight, heaviest first
/// (the "best cluster" of ROS amcl's pf_cluster_stats, computed in O(N) with hashing).
std::vector<ClusterEstimate> ClusterParticles(const ParticleSet& particles, double bin_xy_m,
                                              double bin_yaw_rad);

/// Mean and covariance of all particles.
ClusterEstimate WeightedMean(const ParticleSet& particles);

}  // namespace fleetnav::localization
