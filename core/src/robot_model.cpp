#include "fleetnav/core/robot_model.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "fleetnav/core/angles.hpp"
#include "strings_internal.hpp"

namespace fleetnav {
namespace {

// An axis-aligned rectangle in base_link, counter-clockwise from the rear right corner.
std::vector<Eigen::Vector2d> Rectangle(double rear_x_m, double front_x_m, double half_width_m) {
  return {{rear_x_m, -half_width_m},
          {front_x_m, -half_width_m},
          {front_x_m, half_width_m},
          {rear_x_m, half_width_m}};
}

SensorMount Mount(std::string name, SensorType type, double x_m, double y_m, double yaw_rad,
                  double z_m) {
  return SensorMount{std::move(name), type, Pose2(x_m, y_m, yaw_rad), z_m};
}

// Twice the signed area of a polygon (positive when counter-clockwise).
double TwiceSignedArea(const std::vector<Eigen::Vector2d>& polygon) {
  double sum = 0.0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[(i + 1) % polygon.size()];
    sum += a.x() * b.y() - b.x() * a.y();
  }
  return sum;
}

absl::Status CheckPositive(double value, std::string_view field) {
  if (std::isfinite(value) && value > 0.0) return absl::OkStatus();
  return absl::InvalidArgumentError(
      absl::StrFormat("%s must be finite and > 0, got %g", field, value));
}

absl::Status CheckNonNegative(double value, std::string_view field) {
  if (std::isfinite(value) && value >= 0.0) return absl::OkStatus();
  return absl::InvalidArgumentError(
      absl::StrFormat("%s must be finite and >= 0, got %g", field, value));
}

absl::Status ValidateGeometry(const RobotModel& model) {
  if (model.footprint_m.size() < 3) {
    return absl::InvalidArgumentError(
        absl::StrCat("footprint_m must have at least 3 points, got ", model.footprint_m.size()));
  }
  for (size_t i = 0; i < model.footprint_m.size(); ++i) {
    if (!model.footprint_m[i].allFinite()) {
      return absl::InvalidArgumentError(absl::StrCat("footprint_m[", i, "] must be finite"));
    }
  }
  if (TwiceSignedArea(model.footprint_m) <= 0.0) {
    return absl::InvalidArgumentError(
        "footprint_m must be a counter-clockwise polygon with positive area");
  }
  if (absl::Status s = CheckPositive(model.wheel_radius_m, "wheel_radius_m"); !s.ok()) return s;
  if (absl::Status s = CheckPositive(model.track_m, "track_m"); !s.ok()) return s;
  if (absl::Status s = CheckNonNegative(model.wheelbase_m, "wheelbase_m"); !s.ok()) return s;
  if (model.kinematics != Kinematics::kDifferential) {
    if (absl::Status s = CheckPositive(model.wheelbase_m, "wheelbase_m"); !s.ok()) return s;
  }
  if (model.encoder_ticks_per_rev <= 0) {
    return absl::InvalidArgumentError(
        absl::StrCat("encoder_ticks_per_rev must be > 0, got ", model.encoder_ticks_per_rev));
  }
  if (absl::Status s = CheckPositive(model.mass_kg, "mass_kg"); !s.ok()) return s;
  return CheckPositive(model.height_m, "height_m");
}

absl::Status ValidateLimits(const RobotModel& model) {
  const MotionLimits& limits = model.limits;
  const std::pair<double, std::string_view> all[] = {
      {limits.max_speed_mps, "limits.max_speed_mps"},
      {limits.max_reverse_speed_mps, "limits.max_reverse_speed_mps"},
      {limits.max_yaw_rate_radps, "limits.max_yaw_rate_radps"},
      {limits.max_accel_mps2, "limits.max_accel_mps2"},
      {limits.max_yaw_accel_radps2, "limits.max_yaw_accel_radps2"},
      {limits.max_lateral_speed_mps, "limits.max_lateral_speed_mps"},
      {limits.max_steering_rad, "limits.max_steering_rad"},
      {limits.max_steering_rate_radps, "limits.max_steering_rate_radps"},
  };
  for (const auto& [value, field] : all) {
    if (absl::Status s = CheckNonNegative(value, field); !s.ok()) return s;
  }
  if (absl::Status s = CheckPositive(limits.max_speed_mps, "limits.max_speed_mps"); !s.ok()) {
    return s;
  }
  if (model.kinematics != Kinematics::kOmnidirectional && limits.max_lateral_speed_mps > 0.0) {
    return absl::InvalidArgumentError(
        "limits.max_lateral_speed_mps must be 0 for a robot that is not omnidirectional");
  }
  if (model.kinematics == Kinematics::kAckermann) {
    if (absl::Status s = CheckPositive(limits.max_steering_rad, "limits.max_steering_rad");
        !s.ok()) {
      return s;
    }
    if (limits.max_steering_rad >= kPi / 2.0) {
      return absl::InvalidArgumentError("limits.max_steering_rad must be below pi/2");
    }
  }
  return absl::OkStatus();
}

absl::Status ValidateSensors(const RobotModel& model) {
  std::set<std::string> names;
  for (size_t i = 0; i < model.sensors.size(); ++i) {
    const SensorMount& sensor = model.sensors[i];
    if (sensor.name.empty()) {
      return absl::InvalidArgumentError(absl::StrCat("sensors[", i, "]: name must not be empty"));
    }
    if (!names.insert(sensor.name).second) {
      return absl::InvalidArgumentError(
          absl::StrCat("sensors[", i, "]: duplicate sensor name '", sensor.name, "'"));
    }
    if (!sensor.pose_in_base.IsFinite() || !std::isfinite(sensor.z_m)) {
      return absl::InvalidArgumentError(
          absl::StrCat("sensors[", i, "] (", sensor.name, "): pose must be finite"));
    }
  }
  return absl::OkStatus();
}

}  // namespace

absl::Status RobotModel::Validate() const {
  if (kind_name.empty()) return absl::InvalidArgumentError("kind_name must not be empty");
  if (absl::Status s = ValidateGeometry(*this); !s.ok()) return s;
  if (absl::Status s = ValidateLimits(*this); !s.ok()) return s;
  return ValidateSensors(*this);
}

double RobotModel::CircumscribedRadius() const {
  double radius_m = 0.0;
  for (const Eigen::Vector2d& vertex : footprint_m) radius_m = std::max(radius_m, vertex.norm());
  return radius_m;
}

Eigen::AlignedBox2d RobotModel::FootprintBounds() const {
  Eigen::AlignedBox2d box;
  for (const Eigen::Vector2d& vertex : footprint_m) box.extend(vertex);
  return box;
}

RobotModel RobotModel::CarryingLoad(const Eigen::Vector2d& load_size_m) const {
  RobotModel carrying = *this;
  carrying.footprint_m = FootprintCarrying(load_size_m);
  return carrying;
}

std::vector<Eigen::Vector2d> RobotModel::FootprintCarrying(
    const std::optional<Eigen::Vector2d>& load_size_m) const {
  if (!load_size_m) return footprint_m;
  Eigen::AlignedBox2d box = FootprintBounds();
  box.extend(Eigen::Vector2d(0.5 * load_size_m->x(), 0.5 * load_size_m->y()));
  box.extend(Eigen::Vector2d(-0.5 * load_size_m->x(), -0.5 * load_size_m->y()));
  return {box.corner(Eigen::AlignedBox2d::BottomLeft), box.corner(Eigen::AlignedBox2d::BottomRight),
          box.corner(Eigen::AlignedBox2d::TopRight), box.corner(Eigen::AlignedBox2d::TopLeft)};
}

const SensorMount* RobotModel::FindSensor(std::string_view name) const {
  for (const SensorMount& sensor : sensors) {
    if (sensor.name == name) return &sensor;
  }
  return nullptr;
}

// Lely Vector MFR, thesis ch. 3. The thesis measures from the robot centre C on the floor with
// y forward (Tables 3.2, 3.5, 3.6); here base_link sits at the middle of the drive axle with
// x forward and y left (REP 103), so base_x = thesis_y + 0.26 m and base_y = -thesis_x
// (thesis x points to the robot's right).
RobotModel LelyVectorModel() {
  constexpr double kAxleToCentreM = 0.26;  // drive wheels at thesis y = -260 mm
  constexpr double kLengthM = 2.27;        // Table 3.1
  constexpr double kWidthM = 1.60;         // Table 3.1
  const auto base_x = [](double thesis_y_m) { return thesis_y_m + kAxleToCentreM; };

  RobotModel model;
  model.kind_name = "lely-vector";
  model.kinematics = Kinematics::kDifferential;
  // The body is centred on C. The ultrasonic shelf (thesis y = 1310 mm) reaches 0.175 m past the
  // listed 2.27 m length; the thesis gives no shelf outline, so the footprint is the body only.
  model.footprint_m = Rectangle(base_x(-kLengthM / 2.0), base_x(kLengthM / 2.0), kWidthM / 2.0);
  model.wheel_radius_m = 0.15;  // Ø 300 mm (Table 3.2)
  model.track_m = 0.92;         // wheels at thesis x = ±460 mm
  // Distance from the drive axle to the swivel caster (thesis y = 450 mm): 0.71 m. Not used by
  // differential kinematics; kept for the simulator's caster.
  model.wheelbase_m = base_x(0.45);
  model.encoder_ticks_per_rev = 4096;  // our choice: the thesis (eq. 3.4) gives no resolution
  model.mass_kg = 1485.0;              // Table 3.1
  model.height_m = 1.90;               // Table 3.1

  model.limits.max_speed_mps = 0.5;          // Table 3.1
  model.limits.max_reverse_speed_mps = 0.0;  // §3.2: reversing flips the caster; not allowed
  // Not given in the thesis; chosen for a 1.5 t feeder: gentle accelerations, 0.5 rad/s turns.
  model.limits.max_yaw_rate_radps = 0.5;
  model.limits.max_accel_mps2 = 0.3;
  model.limits.max_yaw_accel_radps2 = 0.5;

  const double ultrasonic_x_m = base_x(1.31);  // Table 3.5; z not given, 0.6 m chosen
  const double inductive_x_m = base_x(0.225);  // Table 3.6
  model.sensors = {
      Mount("wheel_encoder_left", SensorType::kWheelEncoder, 0.0, 0.46, 0.0, 0.15),
      Mount("wheel_encoder_right", SensorType::kWheelEncoder, 0.0, -0.46, 0.0, 0.15),
      Mount("imu", SensorType::kImu, 0.0, 0.0, 0.0, 0.5),  // place not given; on the axle
      Mount("ultrasonic_left", SensorType::kUltrasonic, ultrasonic_x_m, 0.25, kPi / 2.0, 0.6),
      Mount("ultrasonic_right", SensorType::kUltrasonic, ultrasonic_x_m, -0.25, -kPi / 2.0, 0.6),
      Mount("inductive_left", SensorType::kInductive, inductive_x_m, 0.05, 0.0, 0.04),
      Mount("inductive_right", SensorType::kInductive, inductive_x_m, -0.05, 0.0, 0.04),
      // Charger contact and bumper at the front of the body (places chosen, not in the thesis).
      Mount("charger_contact", SensorType::kChargerContact, base_x(kLengthM / 2.0), 0.0, 0.0, 0.3),
      Mount("bumper", SensorType::kBumper, base_x(kLengthM / 2.0), 0.0, 0.0, 0.2),
  };
  return model;
}

// KUKA store platform (KUKA thesis §3: 788 × 480 × 140 mm, mecanum, laser at the front). The
// thesis states the kinematics with symbols only (T_X, T_Y, r, eq. 4.5–4.8), so the wheel
// geometry, mass and limits below are our choices for a platform of that size.
RobotModel MecanumPlatformModel() {
  RobotModel model;
  model.kind_name = "mecanum-platform";
  model.kinematics = Kinematics::kOmnidirectional;
  model.footprint_m = Rectangle(-0.394, 0.394, 0.240);
  model.wheel_radius_m = 0.05;         // chosen
  model.track_m = 0.40;                // chosen: 2 T_Y, wheels just inside the 0.48 m width
  model.wheelbase_m = 0.60;            // chosen: 2 T_X, front to rear wheel axis
  model.encoder_ticks_per_rev = 4096;  // chosen
  model.mass_kg = 60.0;                // chosen (the platform carries 100 kg payload)
  model.height_m = 0.14;               // thesis §3

  model.limits.max_speed_mps = 0.5;  // chosen for indoor store aisles
  model.limits.max_reverse_speed_mps = 0.5;
  model.limits.max_lateral_speed_mps = 0.5;
  model.limits.max_yaw_rate_radps = 1.0;
  model.limits.max_accel_mps2 = 0.5;
  model.limits.max_yaw_accel_radps2 = 1.0;

  model.sensors = {
      Mount("laser", SensorType::kLaser, 0.35, 0.0, 0.0, 0.14),  // "mounted at the front"
      Mount("imu", SensorType::kImu, 0.0, 0.0, 0.0, 0.07),
      Mount("wheel_encoder_front_left", SensorType::kWheelEncoder, 0.30, 0.20, 0.0, 0.05),
      Mount("wheel_encoder_front_right", SensorType::kWheelEncoder, 0.30, -0.20, 0.0, 0.05),
      Mount("wheel_encoder_rear_left", SensorType::kWheelEncoder, -0.30, 0.20, 0.0, 0.05),
      Mount("wheel_encoder_rear_right", SensorType::kWheelEncoder, -0.30, -0.20, 0.0, 0.05),
      Mount("bumper", SensorType::kBumper, 0.394, 0.0, 0.0, 0.07),
  };
  model.has_lift = true;  // it docks under trolleys and lifts them (thesis ch. 15)
  return model;
}

// Ackermann delivery robot (capstone, bicycle model; 2D laser 180° / 30 m, IMU, GPS, encoders).
// The capstone gives no dimensions; we chose a small robot of 0.9 × 0.6 m with a 0.6 m
// wheelbase, base_link at the rear axle, 0.15 m rear overhang.
RobotModel AckermannDeliveryModel() {
  RobotModel model;
  model.kind_name = "ackermann-delivery";
  model.kinematics = Kinematics::kAckermann;
  model.footprint_m = Rectangle(-0.15, 0.75, 0.30);
  model.wheel_radius_m = 0.10;         // chosen
  model.track_m = 0.50;                // chosen
  model.wheelbase_m = 0.60;            // chosen
  model.encoder_ticks_per_rev = 4096;  // chosen
  model.mass_kg = 40.0;                // chosen
  model.height_m = 0.70;               // chosen

  model.limits.max_speed_mps = 1.0;  // chosen; the capstone drives at 0.1 m/s in simulation
  model.limits.max_reverse_speed_mps = 0.3;
  // v / L · tan(steer) = 1.0 / 0.6 · tan(0.5) ≈ 0.91 rad/s at full speed and lock.
  model.limits.max_yaw_rate_radps = 0.9;
  model.limits.max_accel_mps2 = 0.5;
  model.limits.max_yaw_accel_radps2 = 1.0;
  model.limits.max_steering_rad = 0.5;
  model.limits.max_steering_rate_radps = 0.5;

  model.sensors = {
      // 180° field of view, 30 m range (capstone §4.3); the mount carries only the pose.
      Mount("laser", SensorType::kLaser, 0.70, 0.0, 0.0, 0.40),
      Mount("imu", SensorType::kImu, 0.30, 0.0, 0.0, 0.30),
      Mount("gps", SensorType::kGps, 0.30, 0.0, 0.0, 0.70),
      Mount("wheel_encoder_left", SensorType::kWheelEncoder, 0.0, 0.25, 0.0, 0.10),
      Mount("wheel_encoder_right", SensorType::kWheelEncoder, 0.0, -0.25, 0.0, 0.10),
  };
  return model;
}

absl::StatusOr<RobotModel> RobotModelByKind(std::string_view kind_name) {
  if (kind_name == "lely-vector") return LelyVectorModel();
  if (kind_name == "mecanum-platform") return MecanumPlatformModel();
  if (kind_name == "ackermann-delivery") return AckermannDeliveryModel();
  return absl::NotFoundError(
      absl::StrCat("unknown robot kind '", internal::ToAbsl(kind_name),
                   "' (known: lely-vector, mecanum-platform, ackermann-delivery)"));
}

std::string_view KinematicsName(Kinematics kinematics) {
  switch (kinematics) {
    case Kinematics::kDifferential:
      return "differential";
    case Kinematics::kOmnidirectional:
      return "omnidirectional";
    case Kinematics::kAckermann:
      return "ackermann";
  }
  return "differential";
}

}  // namespace fleetnav
