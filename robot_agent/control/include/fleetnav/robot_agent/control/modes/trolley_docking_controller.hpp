#pragma once

#include <optional>
#include <string>

#include "absl/status/status.h"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/robot_agent/control/common/motion_controller.hpp"
#include "fleetnav/robot_agent/laser_filters.hpp"
#include "fleetnav/robot_agent/trolley_recognition.hpp"

namespace fleetnav::agent {

struct TrolleyDockingParams {
  TrolleySpec spec;
  int median_window = 3;          ///< scans in the temporal median filter
  double max_range_m = 4.0;       ///< trolleys farther than this are not docked at
  double search_timeout_s = 3.0;  ///< no trolley seen for this long: the action fails
  double standoff_m = 0.25;       ///< the approach frame's gap before the trolley's legs
  double approach_speed_mps = 0.2;
  double final_speed_mps = 0.08;
  double position_gain_per_s = 1.2;
  double yaw_gain_per_s = 1.5;
  double approach_tolerance_m = 0.01;
  double final_tolerance_m = 0.003;
  double tolerance_rad = 0.01;
  double expected_within_m = 1.0;
  /// A measured trolley whose axis is further than this (either way round) from the expected
  /// one, or from the one being docked at, is another shape of legs.
  double axis_within_rad = 0.5;
  /// At the final frame the lift rises; without a load on it after this long the dock fails.
  double lift_timeout_s = 2.0;
  absl::Status Validate() const;
};

/// Docking under a trolley (KUKA thesis ch. 12–15). Each laser scan goes through the temporal
/// median and shadow filters, clustering, the iterative end-point fit and circle extraction
/// (LegCandidates), and the trolley recognition from leg distances; the trolley within range
/// and near where the site expects it (place and axis), four legs seen before three, gives the
/// dock frames. The platform drives holonomically on its odometry to the
/// approach frame in front of the trolley's near end, re-measuring the trolley as it goes, then
/// straight under it to the final frame (the trolley's centre) measured last from the approach
/// frame, where all four legs are in view, stops and raises its lift, which latches the
/// trolley: the action is done when the lift reports the load. Fails when no trolley is in view
/// within `search_timeout_s`, or when the raised lift carries nothing after `lift_timeout_s`.
/// Not thread-safe.
class TrolleyDockingController : public MotionController {
 public:
  /// `expected_in_map`: where the site says trolley `target_id` stands (the marker set's
  /// trolleys); then only a trolley within `expected_within_m` of it is docked at.
  TrolleyDockingController(const RobotModel& model, TrolleyDockingParams params,
                           std::string target_id = "",
                           std::optional<Pose2> expected_in_map = std::nullopt);
  ControlOutput Step(const ControlInput& input) override;

 private:
  enum class Stage { kSearch, kApproach, kFinal, kLift, kDone };
  /// The trolley in the scan, in the odometry frame, or nullopt.
  std::optional<Pose2> Measure(const ControlInput& input);
  Twist2 DriveTo(const Pose2& target_in_odom, const Pose2& pose_in_odom, double speed_mps,
                 double dt_s);

  RobotModel model_;
  TrolleyDockingParams params_;
  std::string target_id_;
  std::optional<Pose2> expected_in_map_;
  TemporalMedianFilter median_;
  Stage stage_ = Stage::kSearch;
  double searched_s_ = 0.0;
  double lifting_s_ = 0.0;
  std::optional<Pose2> trolley_in_odom_;
  double start_distance_m_ = 0.0;
  Twist2 last_command_;
};

}  // namespace fleetnav::agent
