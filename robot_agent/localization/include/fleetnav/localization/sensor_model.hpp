#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "fleetnav/core/occupancy_grid.hpp"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/core/sensor_frame.hpp"

namespace fleetnav::localization {

/// One range reading expressed in base_link: the beam starts at origin_in_base and points at
/// angle_in_base_rad. A reading without echo (no_echo) reports range_max_m.
struct RangeBeam {
  Eigen::Vector2d origin_in_base = Eigen::Vector2d::Zero();
  double angle_in_base_rad = 0.0;
  double range_m = 0.0;
  double range_max_m = 0.0;
  bool no_echo = false;
  /// Opening angle of a cone-shaped beam (an ultrasonic), whose echo is the nearest surface
  /// anywhere in the cone, not only on its axis; 0: a ray (a laser).
  double cone_rad = 0.0;
};

/// The directions (in base_link) across a beam's cone at which its echo may have come from,
/// at most a degree apart, the axis included; a ray has its axis alone.
std::vector<double> BeamRayAngles(const RangeBeam& beam);

/// The range readings of one update, from one or several sensors.
struct RangeObservation {
  std::vector<RangeBeam> beams;
};

/// A planar laser scan mounted at `mount_in_base`, sub-sampled to at most `max_beams` evenly
/// spaced beams (0: all). Readings ≥ range_max or non-finite become no-echo beams.
RangeObservation ObservationFromLaser(const LaserScanSample& scan, const Pose2& mount_in_base,
                                      int max_beams);

/// The "fake laser" of the Lely thesis §5.2 (eq. 5.2–5.4): each side ultrasonic becomes one
/// beam. The thesis puts base_scan at the midpoint O of the two sensors and adds d/2 to each
/// range; here each beam starts at its own mount, which is the same geometry without the
/// approximation, and each beam keeps the sensor's opening angle `cone_rad` (the thesis
/// simulates its PIL P42 with 10°, §4.3.1): an echo 2.5 m out may come from 5° off the axis,
/// where a wall met at an angle is 8 cm nearer than on it. Unlike eq. 5.2/5.4 (which write 0, i.e.
/// drop the beam) a reading without echo is kept as a no-echo beam: evidence that the beam's path
/// is free. Sensors are matched to mounts by name; readings with no mount are InvalidArgument.
absl::StatusOr<RangeObservation> FakeLaserFromUltrasonics(const std::vector<RangeReading>& readings,
                                                          const RobotModel& model,
                                                          double range_max_m,
                                                          double cone_rad = 0.0);

/// Likelihood-field parameters (Probabilistic Robotics §6.4, Table 6.3). The field stores, per
/// cell, log(z_hit·exp(−d²/2σ²) + z_rand/z_rand_range) for the distance d to the nearest
/// occupied cell (capped at max_distance_m).
struct LikelihoodFieldParams {
  double sigma_hit_m = 0.1;      ///< std. dev. of the end-point distance
  double z_hit = 0.95;           ///< weight of the hit component
  double z_rand = 0.05;          ///< weight of the uniform component
  double z_rand_range_m = 20.0;  ///< range over which z_rand is spread
  double max_distance_m = 2.0;   ///< distance transform cap
  /// No-echo beams: a beam whose path passes at distance d of an obstacle has likelihood
  /// no_echo_floor + (1 − no_echo_floor)·(1 − exp(−d²/2σ_free²)).
  double sigma_free_m = 0.15;
  double no_echo_floor = 0.05;  ///< chance of no echo even though an obstacle is in the beam
  double free_step_m = 0.1;     ///< spacing of the points checked along a no-echo beam
  /// Exponent applied to each beam's log-likelihood (1: independent beams). Values < 1 temper
  /// the over-confidence of many correlated beams.
  double beam_exponent = 1.0;
  absl::Status Validate() const;
};

/// The likelihood field precomputed into float grids: one lookup per beam end point, no exp
/// in the hot loop. Built from an exact Euclidean distance transform (Felzenszwalb and
/// Huttenlocher 2012) of the occupied cells. Unknown cells and points outside the map get the
/// z_rand floor. The map's origin yaw must be 0. Immutable after Create; thread-safe to read.
class LikelihoodField {
 public:
  static absl::StatusOr<LikelihoodField> Create(const OccupancyGrid& grid,
                                                const LikelihoodFieldParams& params);

  /// Log-likelihood of a beam end point at map position (x, y).
  float LogHit(float x_m, float y_m) const { return log_hit_[CellOf(x_m, y_m)]; }
  /// Log-likelihood contribution of a no-echo beam passing through (x, y).
  float LogFree(float x_m, float y_m) const { return log_free_[CellOf(x_m, y_m)]; }
  /// Distance to the nearest occupied cell (capped at max_distance_m).
  float DistanceM(float x_m, float y_m) const { return distance_m_[CellOf(x_m, y_m)]; }
  /// True when (x, y) lies on the map.
  bool Contains(float x_m, float y_m) const { return CellOf(x_m, y_m) != outside_; }
  /// The best value a beam can score (end point on an obstacle).
  float max_log_hit() const { return max_log_hit_; }
  const LikelihoodFieldParams& params() const { return params_; }
  size_t MemoryBytes() const;

  /// Adds, for each of n particles (structure-of-arrays), the log-likelihood of the
  /// observation to log_weight[i]. Returns the number of beams that contributed.
  int Accumulate(const RangeObservation& observation, const float* x, const float* y,
                 const float* yaw, size_t n, float* log_weight) const;

 private:
  LikelihoodField() = default;
  // Cell index with one extra padding cell at index size() for everything outside the map.
  size_t CellOf(float x_m, float y_m) const {
    const float fx = (x_m - origin_x_) * inv_resolution_;
    const float fy = (y_m - origin_y_) * inv_resolution_;
    // Compared as floats first: NaN and huge values must not reach the integer conversion.
    if (!(fx >= 0.0f && fy >= 0.0f && fx < width_f_ && fy < height_f_)) return outside_;
    return static_cast<size_t>(static_cast<int64_t>(fy) * width_ + static_cast<int64_t>(fx));
  }

  LikelihoodFieldParams params_;
  int64_t width_ = 0;
  int64_t height_ = 0;
  float width_f_ = 0.0f;
  float height_f_ = 0.0f;
  float origin_x_ = 0.0f;
  float origin_y_ = 0.0f;
  float inv_resolution_ = 1.0f;
  size_t outside_ = 0;
  float max_log_hit_ = 0.0f;
  std::vector<float> log_hit_;
  std::vector<float> log_free_;
  std::vector<float> distance_m_;
};

/// Beam-model parameters (Probabilistic Robotics §6.3, Table 6.1): mixture of a Gaussian hit,
/// exponential short readings, a max-range spike and uniform noise.
struct BeamModelParams {
  double z_hit = 0.8;
  double z_short = 0.05;
  double z_max = 0.05;
  double z_rand = 0.1;
  double sigma_hit_m = 0.1;
  double lambda_short = 0.5;   ///< 1/m
  double beam_exponent = 1.0;  ///< as LikelihoodFieldParams::beam_exponent
  absl::Status Validate() const;
};

/// Casts a ray through the occupancy grid from `origin` along `angle_rad` and returns the
/// distance to the first occupied cell, or range_max_m when none is met (grid-traversal
/// algorithm of Amanatides and Woo 1987).
double CastRay(const OccupancyGrid& grid, const Eigen::Vector2d& origin, double angle_rad,
               double range_max_m);

/// The beam model: ray casting per particle and beam (expensive; for few particles or beams).
/// A no-echo beam scores p(z = z_max), so free paths are evidence as in the physical model.
/// Immutable; thread-safe to read.
class BeamModel {
 public:
  BeamModel(const OccupancyGrid& grid, const BeamModelParams& params)
      : grid_(grid), params_(params) {}
  int Accumulate(const RangeObservation& observation, const float* x, const float* y,
                 const float* yaw, size_t n, float* log_weight) const;
  /// The log-likelihood of one reading given the expected range.
  double LogLikelihood(double measured_m, double expected_m, double range_max_m,
                       bool no_echo) const;
  const BeamModelParams& params() const { return params_; }

 private:
  OccupancyGrid grid_;
  BeamModelParams params_;
};

}  // namespace fleetnav::localization
