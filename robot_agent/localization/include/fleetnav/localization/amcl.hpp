#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/occupancy_grid.hpp"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/localization/motion_model.hpp"
#include "fleetnav/localization/particle_filter.hpp"
#include "fleetnav/localization/random.hpp"
#include "fleetnav/localization/sensor_model.hpp"

namespace fleetnav::localization {

enum class SensorModelType { kLikelihoodField, kBeam };

/// Parameters of AMCL. Every field has a default that suits a 0.5 m/s robot on a 5 cm map.
struct AmclParams {
  size_t min_particles = 500;   ///< KLD lower bound
  size_t max_particles = 5000;  ///< KLD upper bound; also the global-initialisation count
  double kld_epsilon = 0.05;    ///< KLD error bound ε
  double kld_delta = 0.01;      ///< KLD: 1 − δ is the confidence; z is its normal quantile
  double kld_bin_xy_m = 0.5;
  double kld_bin_yaw_rad = DegToRad(10.0);
  /// Resample only when N_eff < ratio·N (selective resampling, Grisetti et al. 2007).
  double resample_neff_ratio = 0.5;
  /// Augmented MCL (Probabilistic Robotics Table 8.3): averages of the per-beam measurement
  /// likelihood; random particles are injected with probability max(0, 1 − w_fast/w_slow).
  double alpha_slow = 0.001;
  double alpha_fast = 0.1;
  /// Lowest starting value of w_slow: the per-beam likelihood score a converged filter is
  /// expected to reach with a good map. A converged filter scoring below it injects.
  double reference_likelihood_score = 0.5;
  /// Cap on the injected share per resampling: the rest of the set keeps refining the
  /// hypotheses that the random particles found.
  double max_injection_fraction = 1.0;
  /// Injection probabilities below this are treated as noise (no forced resample).
  double recovery_min_probability = 0.05;
  /// Update gate: the sensor update runs after this much travel or rotation, or, when
  /// stationary, every stationary_update_period_s (so the filter still refines at rest).
  double update_min_distance_m = 0.1;
  double update_min_angle_rad = 0.1;
  double stationary_update_period_s = 1.0;
  /// Adaptive tempering while the filter has not yet converged after an initialisation (best
  /// cluster's position stddev above lost_position_stddev_m or its weight share below
  /// converged_cluster_weight, e.g. after global initialisation): the update's
  /// log-likelihoods are scaled by the largest λ in (0, 1] that keeps N_eff ≥ ratio·N, so one
  /// over-confident scan cannot collapse the set onto a wrong mode (annealed importance
  /// sampling, Neal 2001; Deutscher et al. 2000). 0 disables.
  double tempering_min_ess_ratio = 0.1;
  /// The filter counts as converged (tempering off, augmented-MCL averages running) when the
  /// best cluster holds at least this share of the weight and is no wider than
  /// lost_position_stddev_m.
  double converged_cluster_weight = 0.95;
  /// Cluster bins for the estimate (adjacent occupied bins form one cluster).
  double cluster_bin_xy_m = 0.5;
  double cluster_bin_yaw_rad = DegToRad(30.0);
  /// Health: the filter is lost when the per-beam likelihood score stays below
  /// lost_likelihood_score for lost_min_updates updates, when the estimate stays off the map or
  /// within lost_obstacle_distance_m of an occupied cell (inside a wall: no robot is there) for
  /// lost_min_updates updates, or when the best cluster's position standard deviation exceeds
  /// lost_position_stddev_m. Beams that the likelihood field leaves out (short readings of
  /// unmapped obstacles, silent sensors) never show a wrong estimate; its place does.
  double lost_likelihood_score = 0.1;
  int lost_min_updates = 3;
  double lost_position_stddev_m = 1.0;
  double lost_obstacle_distance_m = 0.05;
  /// Roughening (Gordon, Salmond and Smith 1993): after an update that followed travel (not a
  /// turn in place) and whose likelihood score is below roughening_below_score, every particle
  /// is jittered by a zero-mean Gaussian of this
  /// standard deviation in x and y (and roughening_stddev_rad in yaw), so that a cloud made
  /// over-confident by a small motion noise can still reach the truth a few decimetres away
  /// instead of declaring itself lost. 0 disables.
  double roughening_stddev_m = 0.0;
  double roughening_stddev_rad = 0.0;
  double roughening_below_score = 0.3;
  /// Position spread at which the spread factor of the confidence score falls to 1/e.
  double confidence_stddev_m = 0.25;
  MotionModelParams motion;
  SensorModelType sensor_model = SensorModelType::kLikelihoodField;
  LikelihoodFieldParams likelihood_field;
  BeamModelParams beam;
  uint64_t seed = 1;
  absl::Status Validate() const;
};

/// The filter's output (REP 105): best cluster's pose in map, its covariance (x, y, yaw), and the
/// map → odom correction that makes map → odom → base_link equal to it.
struct AmclEstimate {
  Pose2 pose_in_map;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
  Pose2 map_to_odom;
  int64_t stamp_ns = 0;
  size_t particle_count = 0;
  size_t cluster_count = 0;
  double cluster_weight = 0.0;  ///< share of the weight in the best cluster
};

/// Telemetry health: confidence in [0, 1] from the best cluster's spread and weight share and
/// the per-beam measurement likelihood; `lost` when the filter no longer explains the data or
/// is spread over metres.
struct LocalizationHealth {
  double confidence = 0.0;
  bool lost = true;
  std::string lost_reason;        ///< why it is lost, for people
  double likelihood_score = 0.0;  ///< per-beam geometric mean likelihood / its best value
  double position_stddev_m = 0.0;
  double yaw_stddev_rad = 0.0;
};

/// Statistics of the last update, for tests and benchmarks.
struct AmclUpdateStats {
  bool sensor_update = false;
  bool resampled = false;
  size_t injected = 0;
  double effective_sample_size = 0.0;
  double injection_probability = 0.0;
  double tempering = 1.0;  ///< λ applied to this update's log-likelihoods
};

/// Adaptive Monte Carlo localization (Probabilistic Robotics Tables 8.2–8.4; Lely thesis
/// Algorithm 3; Fox 2003 for KLD-sampling) over a 2D occupancy grid. Particles are a
/// structure of arrays (particle_filter.hpp); the likelihood field is a precomputed float
/// grid with one lookup per beam. An update: sample the motion model from the odometry delta,
/// weigh with the sensor model, adapt w_slow/w_fast, resample systematically when N_eff is low
/// (or recovery is needed), sizing the new set by KLD-sampling and injecting random poses over
/// free space with the augmented-MCL probability, then take the best cluster's mean and
/// covariance as the estimate. Not thread-safe; one instance per robot.
class Amcl {
 public:
  static absl::StatusOr<Amcl> Create(const AmclParams& params, const OccupancyGrid& map);

  /// Tracking start: max_particles drawn around pose_in_map with per-axis stddev (x, y, yaw).
  absl::Status InitializePose(const Pose2& pose_in_map, const Eigen::Vector3d& stddev,
                              const Pose2& pose_in_odom, int64_t stamp_ns);
  /// Global start: max_particles uniformly over the free cells, yaw uniform.
  absl::Status InitializeGlobal(const Pose2& pose_in_odom, int64_t stamp_ns);
  bool initialized() const { return initialized_; }

  /// One filter step with the odometry pose and range readings of stamp_ns. Returns whether
  /// the sensor update ran (the update gate may skip it).
  absl::StatusOr<bool> Update(const Pose2& pose_in_odom, const RangeObservation& observation,
                              int64_t stamp_ns);
  /// Applies the motion from the last filter pose to pose_in_odom without a sensor update.
  absl::Status Predict(const Pose2& pose_in_odom);
  /// Predict, once the robot has moved update_min_distance_m or turned update_min_angle_rad
  /// since the last filter pose; returns whether it did. For stretches without range readings:
  /// the motion model's noise must be drawn step by step, not once over metres (one draw over
  /// 13 m spreads the cloud metres sideways).
  absl::StatusOr<bool> PredictIfMoved(const Pose2& pose_in_odom);

  /// Pieces of Update, public for SAMCL and the benchmarks.
  void Weigh(const RangeObservation& observation);
  void Resample();
  void RecomputeEstimate(int64_t stamp_ns);

  const AmclEstimate& estimate() const { return estimate_; }
  const LocalizationHealth& health() const { return health_; }
  const AmclUpdateStats& last_update() const { return stats_; }
  /// The pose of base_link in map for a newer odometry pose (map → odom held fixed).
  Pose2 PoseInMap(const Pose2& pose_in_odom) const { return estimate_.map_to_odom * pose_in_odom; }
  const Pose2& filter_pose_in_odom() const { return filter_odom_; }
  const ParticleSet& particles() const { return particles_; }
  ParticleSet& mutable_particles() { return particles_; }
  const AmclParams& params() const { return params_; }
  const LikelihoodField& likelihood_field() const { return *field_; }
  double w_slow() const { return w_slow_; }
  double w_fast() const { return w_fast_; }
  Rng& rng() { return rng_; }
  /// Draws a random pose over the map's free space.
  Pose2 RandomFreePose();

 private:
  Amcl(const AmclParams& params, std::unique_ptr<LikelihoodField> field,
       std::unique_ptr<BeamModel> beam, const OccupancyGrid& map);
  void UpdateHealth(int64_t stamp_ns);
  /// Jitters every particle (AmclParams::roughening_stddev_m / _rad).
  void Roughen();
  /// Counts an update whose estimate is off the map or inside an obstacle, and sets
  /// health_.lost.
  void CountPlace(const Pose2& pose_in_map);
  bool GloballyUncertain() const;

  AmclParams params_;
  std::unique_ptr<LikelihoodField> field_;
  std::unique_ptr<BeamModel> beam_;
  double map_resolution_m_ = 0.05;
  Pose2 map_origin_;
  int map_width_ = 0;
  std::vector<uint32_t> free_cells_;
  Rng rng_;
  ParticleSet particles_;
  std::vector<uint32_t> indices_;
  bool initialized_ = false;
  bool force_update_ = true;
  Pose2 filter_odom_;
  int64_t last_sensor_update_ns_ = 0;
  double w_slow_ = 0.0;
  double w_fast_ = 0.0;
  double last_score_ = 1.0;
  int low_score_updates_ = 0;
  int impossible_place_updates_ = 0;
  AmclEstimate estimate_;
  LocalizationHealth health_;
  AmclUpdateStats stats_;
};

}  // namespace fleetnav::localization
