#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "fleetnav/core/robot_state.hpp"

namespace fleetnav {

struct EncoderReading {
  std::string name;
  int64_t ticks = 0;  ///< cumulative since start
};

struct ImuSample {
  double gyro_z_radps = 0.0;
  double accel_x_mps2 = 0.0;
  double accel_y_mps2 = 0.0;
};

struct RangeReading {
  std::string name;
  double range_m = 0.0;  ///< max range when there is no echo
  bool echo = false;
};

/// One inductive stripe sensor (Lely thesis §3.3, Table 3.6): `detected` when the sensor's
/// point is over metal (a stripe or a marker crossed); `lateral_offset_m`, when a stripe runs
/// under the sensor's lateral measuring line within its range, is where it crosses that line
/// (sensor frame, positive to the left) — the analog reading stripe following steers on.
struct InductiveSample {
  std::string name;
  bool detected = false;
  std::optional<double> lateral_offset_m;
};

struct LaserScanSample {
  std::string name;
  double angle_min_rad = 0.0;
  double angle_increment_rad = 0.0;
  double range_max_m = 0.0;
  std::vector<float> ranges_m;
};

struct GpsFix {
  double x_m = 0.0;
  double y_m = 0.0;
  double stddev_m = 0.0;
};

/// Everything a robot's sensors report in one control tick, stamped with the tick and the
/// (simulated or real) time. The HAL delivers one frame per tick; the agent answers with one
/// ActuatorCommand for the same tick.
struct SensorFrame {
  uint64_t tick = 0;
  int64_t stamp_ns = 0;
  double control_period_s = 0.0;
  std::vector<EncoderReading> encoders;  ///< differential: "left", "right"
  ImuSample imu;
  std::vector<RangeReading> ultrasonic;
  std::vector<InductiveSample> inductive;
  std::vector<LaserScanSample> lasers;
  bool charger_contact = false;
  bool bumper = false;
  /// The lift (robots that have one) carries a load: a trolley rests on it.
  bool lift_loaded = false;
  /// Ackermann robots: the measured steering angle of the virtual front wheel (bicycle model),
  /// positive left.
  std::optional<double> steering_angle_rad;
  /// State of charge in [0, 1], when the robot reports one.
  std::optional<double> battery_fraction;
  std::optional<GpsFix> gps;
  /// In a simulated run, on fleetnavd's ticks: the robots whose agents take part in the tick's
  /// lockstep barrier, sorted (fleetnavd waits for their reports before it runs the tick).
  /// Empty on the simulator's other ticks and on hardware.
  std::vector<std::string> lockstep_robot_ids;
  /// In a simulated run: the simulation holds after this tick (fleetnav-scenario acts there),
  /// so the agent waits for fleetnavd to have taken in the tick before it answers.
  bool holds_after = false;

  const EncoderReading* FindEncoder(std::string_view name) const {
    for (const EncoderReading& e : encoders) {
      if (e.name == name) return &e;
    }
    return nullptr;
  }
};

/// Wheel angular velocities for a differential drive.
struct WheelSpeeds {
  double left_radps = 0.0;
  double right_radps = 0.0;
};

/// Speed and steering angle for an Ackermann drive.
struct AckermannDrive {
  double speed_mps = 0.0;
  double steering_rad = 0.0;
};

/// What the agent tells the actuators for one tick: a body twist (tracked by the robot's own
/// motor controller), wheel speeds, or an Ackermann command; and where the lift should be
/// (robots with a lift: raised under a trolley latches it, lowered sets it down).
struct ActuatorCommand {
  uint64_t tick = 0;
  std::variant<Twist2, WheelSpeeds, AckermannDrive> drive = Twist2{};
  bool lift_raised = false;
};

}  // namespace fleetnav
