#include "fleetnav/robot_agent/perception.hpp"

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
  for (const InductiveSample& s : frame.inductive) {
    if (s.name == "inductive_left") out.inductive_left = s.detected;
    if (s.name == "inductive_right") out.inductive_right = s.detected;
  }
  out.charger_contact = frame.charger_contact;
  out.bumper = frame.bumper;
  return out;
}

}  // namespace fleetnav::agent
