#pragma once

#include <optional>
#include <string>
#include <utility>

#include "absl/status/statusor.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/core/sensor_frame.hpp"

namespace fleetnav::agent {

/// What the reactive controllers and end conditions see of one tick, in the robot's terms.
/// Fence distances are measured from the ultrasonic sensor along its beam (thesis §5.3);
/// nullopt when the sensor heard no echo. Inductive flags are per sensor.
struct Perception {
  std::optional<double> fence_left_m;
  std::optional<double> fence_right_m;
  bool inductive_left = false;
  bool inductive_right = false;
  bool inductive_any() const { return inductive_left || inductive_right; }
  /// Where the followed stripe runs under the inductive sensors, in base_link's y (positive
  /// left), averaged over the sensors that read it; nullopt when none does.
  std::optional<double> stripe_offset_m;
  /// x in base_link of the inductive sensors' lateral line (0 when the robot has none).
  double stripe_sensor_x_m = 0.0;
  bool charger_contact = false;
  bool bumper = false;
  /// The lift carries a load (a trolley is latched on it).
  bool lift_loaded = false;
  /// The laser's scan, on the ticks a new one arrived (10 Hz), and where the laser sits.
  std::optional<LaserScanSample> laser;
  Pose2 laser_in_base;
  int64_t stamp_ns = 0;
};

/// Turns a sensor frame into a Perception for a robot model: ultrasonics named
/// "ultrasonic_left"/"ultrasonic_right" and inductive sensors "inductive_left"/
/// "inductive_right" (the Lely layout); other robots simply have no fence or stripe readings.
/// Readings at or beyond `ultrasonic_range_max_m` count as no echo. Stateless.
class PerceptionBuilder {
 public:
  explicit PerceptionBuilder(RobotModel model, double ultrasonic_range_max_m = 2.5)
      : model_(std::move(model)), ultrasonic_range_max_m_(ultrasonic_range_max_m) {}
  Perception Build(const SensorFrame& frame) const;

 private:
  RobotModel model_;
  double ultrasonic_range_max_m_;
};

}  // namespace fleetnav::agent
