#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "fleetnav/core/pose2.hpp"

namespace fleetnav {

enum class Kinematics { kDifferential, kOmnidirectional, kAckermann };

enum class SensorType {
  kWheelEncoder,
  kImu,
  kUltrasonic,
  kInductive,
  kLaser,
  kChargerContact,
  kBumper,
  kGps,
};

/// A sensor's place on the robot: pose in base_link (x forward, y left, REP 103) and height.
struct SensorMount {
  std::string name;
  SensorType type = SensorType::kImu;
  Pose2 pose_in_base;
  double z_m = 0.0;
};

/// Speed, yaw-rate and acceleration limits (absolute values).
struct MotionLimits {
  double max_speed_mps = 0.5;
  double max_reverse_speed_mps = 0.0;  ///< 0: the robot must not reverse
  double max_yaw_rate_radps = 0.5;
  double max_accel_mps2 = 0.5;
  double max_yaw_accel_radps2 = 1.0;
  double max_lateral_speed_mps = 0.0;  ///< > 0 only for omnidirectional robots
  double max_steering_rad = 0.0;       ///< Ackermann only
  double max_steering_rate_radps = 0.0;
};

/// The geometry and limits of one robot kind. Frames: base_link at the centre of the drive
/// axle for differential drive (x forward), at the platform centre for omni, at the rear axle
/// for Ackermann. footprint_m is a polygon in base_link, counter-clockwise. Wheel geometry:
/// wheel_radius_m; track_m (distance between left and right wheels); wheelbase_m (front to
/// rear axle; for mecanum, the distance between the front and rear wheel axes).
/// encoder_ticks_per_rev is the resolution of the wheel encoders (thesis eq. 3.4). Value type.
struct RobotModel {
  std::string kind_name;  ///< e.g. "lely-vector", "mecanum-platform", "ackermann-delivery"
  Kinematics kinematics = Kinematics::kDifferential;
  std::vector<Eigen::Vector2d> footprint_m;
  double wheel_radius_m = 0.15;
  double track_m = 0.92;
  double wheelbase_m = 0.0;
  int encoder_ticks_per_rev = 4096;
  double mass_kg = 100.0;
  double height_m = 1.0;
  MotionLimits limits;
  std::vector<SensorMount> sensors;
  /// A lift under the platform that raises a trolley the robot stands under (KUKA thesis's
  /// final dock frame): the trolley is then carried.
  bool has_lift = false;

  absl::Status Validate() const;
  /// Radius of the smallest circle around base_link containing the footprint.
  double CircumscribedRadius() const;
  /// The footprint's axis-aligned bounding box in base_link.
  Eigen::AlignedBox2d FootprintBounds() const;
  const SensorMount* FindSensor(std::string_view name) const;
  /// This robot carrying a load of `load_size_m` (length along x, width along y) centred on
  /// base_link, as the planner and the tracker must see it: the footprint grown to the bounding
  /// box of both.
  RobotModel CarryingLoad(const Eigen::Vector2d& load_size_m) const;
  /// The footprint of CarryingLoad(*load_size_m), or the bare footprint without a load.
  std::vector<Eigen::Vector2d> FootprintCarrying(
      const std::optional<Eigen::Vector2d>& load_size_m) const;
};

/// Lely Vector MFR (thesis ch. 3): 2.27 × 1.60 m footprint, 1485 kg, wheels Ø 300 mm on a
/// 0.92 m track, swivel caster 0.71 m ahead of the axle, 0.5 m/s, never reverses; two side
/// ultrasonics, two inductive stripe sensors, gyro/IMU, wheel encoders, charger contact, bumper.
RobotModel LelyVectorModel();
/// Mecanum store platform (KUKA thesis): 0.788 × 0.480 m, omnidirectional, 2D laser.
RobotModel MecanumPlatformModel();
/// Ackermann delivery robot (capstone): bicycle model, 180° laser, GPS, IMU, encoders.
RobotModel AckermannDeliveryModel();
/// The preset for a kind name, or NotFound.
absl::StatusOr<RobotModel> RobotModelByKind(std::string_view kind_name);

std::string_view KinematicsName(Kinematics kinematics);

}  // namespace fleetnav
