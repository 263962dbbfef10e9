#include "fleetnav/robot_agent/telemetry_recorder.hpp"

namespace fleetnav::agent {

void TelemetryRecorder::Publish(const Telemetry& telemetry) {
  *out_ << robot_id_ << ",estimate," << telemetry.pose_in_map.x_m() << ','
        << telemetry.pose_in_map.y_m() << ',' << telemetry.stamp_ns * 1e-9 << ','
        << NavigationModeName(telemetry.mode) << ',' << telemetry.action_index << '\n';
  if (next_ != nullptr) next_->Publish(telemetry);
}

}  // namespace fleetnav::agent
