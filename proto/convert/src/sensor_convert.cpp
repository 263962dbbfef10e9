#include "fleetnav/proto/sensor_convert.hpp"

#include <cmath>

namespace fleetnav {

v1::SensorFrame ToProto(const SensorFrame& frame) {
  v1::SensorFrame out;
  out.set_tick(frame.tick);
  out.set_sim_time_ns(frame.stamp_ns);
  out.set_control_period_s(frame.control_period_s);
  for (const std::string& id : frame.lockstep_robot_ids) out.add_lockstep_robot_ids(id);
  out.set_holds_after(frame.holds_after);
  for (const EncoderReading& e : frame.encoders) {
    v1::WheelEncoderReading* wire = out.add_encoders();
    wire->set_name(e.name);
    wire->set_ticks(e.ticks);
  }
  out.mutable_imu()->set_gyro_z_radps(frame.imu.gyro_z_radps);
  out.mutable_imu()->set_accel_x_mps2(frame.imu.accel_x_mps2);
  out.mutable_imu()->set_accel_y_mps2(frame.imu.accel_y_mps2);
  for (const RangeReading& r : frame.ultrasonic) {
    v1::UltrasonicReading* wire = out.add_ultrasonic();
    wire->set_name(r.name);
    wire->set_range_m(r.range_m);
    wire->set_echo(r.echo);
  }
  for (const InductiveSample& s : frame.inductive) {
    v1::InductiveReading* wire = out.add_inductive();
    wire->set_name(s.name);
    wire->set_detected(s.detected);
    if (s.lateral_offset_m) {
      wire->set_has_lateral_offset(true);
      wire->set_lateral_offset_m(*s.lateral_offset_m);
    }
  }
  for (const LaserScanSample& scan : frame.lasers) {
    v1::LaserScan* wire = out.add_lasers();
    wire->set_name(scan.name);
    wire->set_angle_min_rad(scan.angle_min_rad);
    wire->set_angle_increment_rad(scan.angle_increment_rad);
    wire->set_range_max_m(scan.range_max_m);
    wire->mutable_ranges_m()->Add(scan.ranges_m.begin(), scan.ranges_m.end());
  }
  out.set_charger_contact(frame.charger_contact);
  out.set_bumper(frame.bumper);
  out.set_lift_loaded(frame.lift_loaded);
  if (frame.steering_angle_rad) {
    out.set_has_steering_angle(true);
    out.set_steering_angle_rad(*frame.steering_angle_rad);
  }
  if (frame.battery_fraction) {
    out.set_has_battery(true);
    out.set_battery_fraction(*frame.battery_fraction);
  }
  if (frame.gps) {
    out.mutable_gps()->set_x_m(frame.gps->x_m);
    out.mutable_gps()->set_y_m(frame.gps->y_m);
    out.mutable_gps()->set_stddev_m(frame.gps->stddev_m);
  }
  return out;
}

SensorFrame FromProto(const v1::SensorFrame& frame) {
  SensorFrame out;
  out.tick = frame.tick();
  out.stamp_ns = frame.sim_time_ns();
  out.control_period_s = frame.control_period_s();
  out.lockstep_robot_ids.assign(frame.lockstep_robot_ids().begin(),
                                frame.lockstep_robot_ids().end());
  out.holds_after = frame.holds_after();
  for (const auto& e : frame.encoders()) out.encoders.push_back({e.name(), e.ticks()});
  out.imu = {frame.imu().gyro_z_radps(), frame.imu().accel_x_mps2(), frame.imu().accel_y_mps2()};
  for (const auto& r : frame.ultrasonic())
    out.ultrasonic.push_back({r.name(), r.range_m(), r.echo()});
  for (const auto& s : frame.inductive()) {
    InductiveSample sample{s.name(), s.detected(), std::nullopt};
    if (s.has_lateral_offset()) sample.lateral_offset_m = s.lateral_offset_m();
    out.inductive.push_back(sample);
  }
  for (const auto& scan : frame.lasers()) {
    out.lasers.push_back({scan.name(), scan.angle_min_rad(), scan.angle_increment_rad(),
                          scan.range_max_m(),
                          std::vector<float>(scan.ranges_m().begin(), scan.ranges_m().end())});
  }
  out.charger_contact = frame.charger_contact();
  out.bumper = frame.bumper();
  out.lift_loaded = frame.lift_loaded();
  if (frame.has_steering_angle()) out.steering_angle_rad = frame.steering_angle_rad();
  if (frame.has_battery()) out.battery_fraction = frame.battery_fraction();
  if (frame.has_gps())
    out.gps = GpsFix{frame.gps().x_m(), frame.gps().y_m(), frame.gps().stddev_m()};
  return out;
}

namespace {

struct DriveToProto {
  v1::ActuatorCommand* out;
  void operator()(const Twist2& twist) const {
    out->mutable_twist()->set_vx_mps(twist.vx_mps);
    out->mutable_twist()->set_vy_mps(twist.vy_mps);
    out->mutable_twist()->set_yaw_rate_radps(twist.yaw_rate_radps);
  }
  void operator()(const WheelSpeeds& wheels) const {
    out->mutable_differential()->set_left_wheel_radps(wheels.left_radps);
    out->mutable_differential()->set_right_wheel_radps(wheels.right_radps);
  }
  void operator()(const AckermannDrive& drive) const {
    out->mutable_ackermann()->set_speed_mps(drive.speed_mps);
    out->mutable_ackermann()->set_steering_rad(drive.steering_rad);
  }
};

bool AllFinite(std::initializer_list<double> values) {
  for (double v : values) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}

}  // namespace

v1::ActuatorCommand ToProto(const ActuatorCommand& command) {
  v1::ActuatorCommand out;
  out.set_tick(command.tick);
  std::visit(DriveToProto{&out}, command.drive);
  out.set_lift_raised(command.lift_raised);
  return out;
}

absl::StatusOr<ActuatorCommand> FromProto(const v1::ActuatorCommand& command) {
  ActuatorCommand out;
  out.tick = command.tick();
  out.lift_raised = command.lift_raised();
  switch (command.command_case()) {
    case v1::ActuatorCommand::kTwist: {
      const auto& t = command.twist();
      if (!AllFinite({t.vx_mps(), t.vy_mps(), t.yaw_rate_radps()})) break;
      out.drive = Twist2{t.vx_mps(), t.vy_mps(), t.yaw_rate_radps()};
      return out;
    }
    case v1::ActuatorCommand::kDifferential: {
      const auto& d = command.differential();
      if (!AllFinite({d.left_wheel_radps(), d.right_wheel_radps()})) break;
      out.drive = WheelSpeeds{d.left_wheel_radps(), d.right_wheel_radps()};
      return out;
    }
    case v1::ActuatorCommand::kAckermann: {
      const auto& a = command.ackermann();
      if (!AllFinite({a.speed_mps(), a.steering_rad()})) break;
      out.drive = AckermannDrive{a.speed_mps(), a.steering_rad()};
      return out;
    }
    case v1::ActuatorCommand::COMMAND_NOT_SET:
      return absl::InvalidArgumentError("command: no drive command set");
  }
  return absl::InvalidArgumentError("command: values must be finite");
}

}  // namespace fleetnav
