#include "fleetnav/localization/odometry_front_end.hpp"

#include <array>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/angles.hpp"

namespace fleetnav::localization {
namespace {

constexpr std::array<const char*, 2> kDiffWheels = {"left", "right"};
constexpr std::array<const char*, 4> kMecanumWheels = {"front_left", "front_right", "rear_left",
                                                       "rear_right"};

DiffDriveOdometryParams DiffParams(const RobotModel& model) {
  DiffDriveOdometryParams p;
  p.wheel_radius_m = model.wheel_radius_m;
  p.track_m = model.track_m;
  p.encoder_ticks_per_rev = model.encoder_ticks_per_rev;
  return p;
}

MecanumOdometryParams MecanumParams(const RobotModel& model) {
  MecanumOdometryParams p;
  p.wheel_radius_m = model.wheel_radius_m;
  p.half_wheelbase_m = 0.5 * model.wheelbase_m;
  p.half_track_m = 0.5 * model.track_m;
  return p;
}

}  // namespace

OdomEkfParams DefaultFrontEndEkfParams() {
  OdomEkfParams p;
  p.wheel_yaw_rate_stddev_radps = 1.0;
  p.gyro_bias_walk_radps = 1e-6;
  return p;
}

absl::Status OdometryFrontEndParams::Validate() const {
  if (!(std::isfinite(standstill_after_s) && standstill_after_s >= 0.0)) {
    return absl::InvalidArgumentError("standstill_after_s: must be finite and >= 0");
  }
  return ekf.Validate();
}

OdometryFrontEnd::OdometryFrontEnd(const RobotModel& model, const OdometryFrontEndParams& params)
    : model_(model),
      params_(params),
      ekf_(params.ekf),
      diff_(DiffParams(model)),
      mecanum_(MecanumParams(model)),
      ackermann_(AckermannOdometryParams{model.wheelbase_m}) {}

absl::StatusOr<OdometryFrontEnd> OdometryFrontEnd::Create(const RobotModel& model,
                                                          const OdometryFrontEndParams& params) {
  if (absl::Status s = params.Validate(); !s.ok()) return s;
  if (model.kinematics == Kinematics::kOmnidirectional) {
    if (absl::Status s = MecanumParams(model).Validate(); !s.ok()) {
      return absl::InvalidArgumentError(absl::StrCat(model.kind_name, ": ", s.message()));
    }
  } else if (absl::Status s = DiffParams(model).Validate(); !s.ok()) {
    return absl::InvalidArgumentError(absl::StrCat(model.kind_name, ": ", s.message()));
  }
  if (model.kinematics == Kinematics::kAckermann) {
    if (absl::Status s = AckermannOdometryParams{model.wheelbase_m}.Validate(); !s.ok()) {
      return absl::InvalidArgumentError(absl::StrCat(model.kind_name, ": ", s.message()));
    }
  }
  return OdometryFrontEnd(model, params);
}

Twist2 OdometryFrontEnd::velocity() const {
  const Eigen::Vector3d t = ekf_.twist();
  return Twist2{t.x(), t.y(), t.z()};
}

absl::Status OdometryFrontEnd::Update(const SensorFrame& frame) {
  const bool omni = model_.kinematics == Kinematics::kOmnidirectional;
  std::map<std::string, int64_t> ticks;
  const auto read = [&](const char* name) -> absl::Status {
    const EncoderReading* e = frame.FindEncoder(name);
    if (e == nullptr) {
      return absl::InvalidArgumentError(absl::StrCat(
          "frame has no '", name, "' wheel encoder, which ", model_.kind_name, " odometry needs"));
    }
    ticks[name] = e->ticks;
    return absl::OkStatus();
  };
  if (omni) {
    for (const char* name : kMecanumWheels) {
      if (absl::Status s = read(name); !s.ok()) return s;
    }
  } else {
    for (const char* name : kDiffWheels) {
      if (absl::Status s = read(name); !s.ok()) return s;
    }
  }
  if (!last_stamp_ns_) {
    last_stamp_ns_ = frame.stamp_ns;
    last_ticks_ = ticks;
    if (!omni) (void)diff_.Update(ticks["left"], ticks["right"]);
    return absl::OkStatus();
  }
  const double dt_s = static_cast<double>(frame.stamp_ns - *last_stamp_ns_) * 1e-9;
  if (dt_s <= 0.0) return absl::OkStatus();

  BodyIncrement increment;
  bool moved = false;
  for (const auto& [name, value] : ticks) moved |= value != last_ticks_[name];
  if (omni) {
    std::array<double, 4> wheel_rad{};
    for (size_t i = 0; i < kMecanumWheels.size(); ++i) {
      const int64_t delta = ticks[kMecanumWheels[i]] - last_ticks_[kMecanumWheels[i]];
      wheel_rad[i] = 2.0 * kPi * static_cast<double>(delta) / model_.encoder_ticks_per_rev;
    }
    increment = mecanum_.Update(wheel_rad);
  } else {
    increment = diff_.Update(ticks["left"], ticks["right"]);
    if (params_.ackermann_yaw_from_steering && model_.kinematics == Kinematics::kAckermann &&
        frame.steering_angle_rad) {
      // The rear axle's arc from the encoders, the turn from the steering angle.
      increment = ackermann_.Update(increment.forward_m, *frame.steering_angle_rad);
    }
  }
  last_ticks_ = ticks;
  last_stamp_ns_ = frame.stamp_ns;

  wheel_velocity_ =
      Twist2{increment.forward_m / dt_s, increment.lateral_m / dt_s, increment.yaw_rad / dt_s};
  distance_m_ += std::hypot(increment.forward_m, increment.lateral_m);
  still_s_ = moved ? 0.0 : still_s_ + dt_s;

  if (absl::Status s = ekf_.Predict(dt_s); !s.ok()) return s;
  ekf_.FuseWheelTwist(Eigen::Vector3d(wheel_velocity_.vx_mps, omni ? wheel_velocity_.vy_mps : 0.0,
                                      wheel_velocity_.yaw_rate_radps));
  // A standing robot does not turn, whatever its gyro's bias says (zero-velocity update).
  if (!standing_still()) ekf_.FuseGyro(frame.imu.gyro_z_radps);
  return absl::OkStatus();
}

}  // namespace fleetnav::localization
