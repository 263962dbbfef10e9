#include "fleetnav/robot_agent/perception.hpp"

#include <utility>

namespace fleetnav::agent {

Perception PerceptionBuilder::Build(const SensorFrame& frame) const {
  Perception out;
  out.stamp_ns = frame.stamp_ns;
  for (const RangeReading& r : frame.ultrasonic) {
    std::optional<double> range;
    if (r.echo && r.range_m < ultrasonic_range_max_m_) range = r.range_m;
    if (r.name == "ultrasonic_left") out.fence_left_m = range;
    if (r.name == "ultrasonic_right") out.fence_right_m = range;
  }
  double offset_sum = 0.0;
  int offsets = 0;
  for (const InductiveSample& s : frame.inductive) {
    if (s.name == "inductive_left") out.inductive_left = s.detected;
    if (s.name == "inductive_right") out.inductive_right = s.detected;
    const SensorMount* mount = model_.FindSensor(s.name);
    if (mount == nullptr) continue;
    out.stripe_sensor_x_m = mount->pose_in_base.x_m();
    if (!s.lateral_offset_m) continue;
    offset_sum += mount->pose_in_base.y_m() + *s.lateral_offset_m;
    ++offsets;
  }
  if (offsets > 0) out.stripe_offset_m = offset_sum / offsets;
  if (!frame.lasers.empty()) {
    if (const SensorMount* mount = model_.FindSensor(frame.lasers.front().name)) {
      out.laser = frame.lasers.front();
      out.laser_in_base = mount->pose_in_base;
    }
  }
  out.charger_contact = frame.charger_contact;
  out.bumper = frame.bumper;
  out.lift_loaded = frame.lift_loaded;
  return out;
}

}  // namespace fleetnav::agent
