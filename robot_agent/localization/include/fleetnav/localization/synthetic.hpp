#pragma once

#include <cstdint>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/occupancy_grid.hpp"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/core/stripe_marker.hpp"
#include "fleetnav/localization/amcl.hpp"
#include "fleetnav/localization/random.hpp"
#include "fleetnav/localization/samcl.hpp"
#include "fleetnav/localization/sensor_model.hpp"

namespace fleetnav::localization {

/// A 26 m × 26 m barn like sim/worlds/barn.yaml (Lely thesis Fig. 1.3): outer walls, feeding
/// fences along y = ±5.9 from x = −10 to 10, the feed kitchen in the east, the charging pole in
/// the west, plus a few posts and boxes away from the north feed alley so that the map has no
/// symmetry. Origin yaw 0, barn centre at (0, 0).
absl::StatusOr<OccupancyGrid> SyntheticBarnMap(double resolution_m);

/// The two calibration markers of Experiment 2: (0, 4.7) and (5, 4.7), across the alley.
MarkerSet Experiment2Markers();

/// A 360° laser scan with `beams` beams from `pose_in_map` (sensor at base_link), Gaussian
/// range noise, readings beyond range_max reported as no echo.
RangeObservation SimulateLaser(const OccupancyGrid& map, const Pose2& pose_in_map, int beams,
                               double range_max_m, double noise_stddev_m, Rng& rng);

/// The side ultrasonics of `model` (sensors of type kUltrasonic) as readings.
std::vector<RangeReading> SimulateUltrasonics(const OccupancyGrid& map, const Pose2& pose_in_map,
                                              const RobotModel& model, double range_max_m,
                                              double noise_stddev_m, Rng& rng);

/// Thesis Experiment 2 on synthetic data: the Lely robot drives from (−5.5, 4.7, 0) along the
/// north fence at speed_mps with only its ultrasonics, with an odometry scale error drawn in
/// [scale_error_min, scale_error_max] (random sign), crossing the markers at x = 0 and 5.
struct Experiment2Params {
  double speed_mps = 0.25;
  double end_x_m = 6.5;
  /// The simulator's sensor rate (50 Hz): the inductive sensor is sampled once a tick.
  double tick_s = 0.02;
  /// Width of the marker strips: the sensor reads metal while its point is over one.
  double marker_width_m = 0.05;
  double scale_error_min = 0.01;
  double scale_error_max = 0.02;
  /// Heading noise per tick: the random walk of 2e-4 rad per 0.1 s tick, at 50 Hz.
  double yaw_noise_per_tick_rad = 8.9e-5;
  double ultrasonic_range_max_m = 2.5;
  double ultrasonic_noise_m = 0.01;
  size_t particles = 500;
  bool use_samcl = true;
  SamclMode samcl_mode = SamclMode::kHard;
};

struct Experiment2Result {
  /// |error| right after each calibration the filter applied (SAMCL), or right after each
  /// sampled rising edge (plain AMCL, which uses none).
  std::vector<double> along_track_after_marker_m;
  std::vector<double> along_track_before_marker_m;  ///< |error| at each sampled rising edge
  double along_track_final_m = 0.0;
  double along_track_mid_m = 0.0;  ///< at x = 0.5 (half way)
  double lateral_max_m = 0.0;
  int calibrations = 0;
};

absl::StatusOr<Experiment2Result> RunExperiment2(const Experiment2Params& params, uint64_t seed);

}  // namespace fleetnav::localization
