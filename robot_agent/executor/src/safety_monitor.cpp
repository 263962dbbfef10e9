#include "fleetnav/robot_agent/safety_monitor.hpp"

#include <cmath>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace fleetnav::agent {

absl::Status SafetyParams::Validate() const {
  for (double v : {stall_after_s, stall_command_mps, stall_command_radps, stall_measured_mps,
                   stall_measured_radps, lost_after_s, stop_after_link_loss_s}) {
    if (!(std::isfinite(v) && v >= 0.0)) {
      return absl::InvalidArgumentError("safety parameters: must be finite and >= 0");
    }
  }
  return absl::OkStatus();
}

void SafetyMonitor::Reset() {
  verdict_ = SafetyVerdict{};
  stalled_s_ = 0.0;
  lost_s_ = 0.0;
}

const SafetyVerdict& SafetyMonitor::Check(const Perception& perception, const Twist2& commanded,
                                          const Twist2& measured, bool localization_lost,
                                          double dt_s, std::string_view lost_reason) {
  if (verdict_.stop != SafetyStop::kNone) return verdict_;
  if (perception.bumper) {
    verdict_ = {SafetyStop::kBumper, "bumper pressed: the robot touched something and stopped"};
    return verdict_;
  }
  const bool commanding = std::abs(commanded.vx_mps) >= params_.stall_command_mps ||
                          std::abs(commanded.vy_mps) >= params_.stall_command_mps ||
                          std::abs(commanded.yaw_rate_radps) >= params_.stall_command_radps;
  const bool still = std::hypot(measured.vx_mps, measured.vy_mps) <= params_.stall_measured_mps &&
                     std::abs(measured.yaw_rate_radps) <= params_.stall_measured_radps;
  stalled_s_ = commanding && still ? stalled_s_ + dt_s : 0.0;
  if (stalled_s_ >= params_.stall_after_s) {
    verdict_ = {SafetyStop::kStall,
                absl::StrFormat("stalled: motion commanded (%.2f m/s, %.2f rad/s) but none "
                                "measured for %.1f s",
                                commanded.vx_mps, commanded.yaw_rate_radps, stalled_s_)};
    return verdict_;
  }
  lost_s_ = localization_lost ? lost_s_ + dt_s : 0.0;
  if (localization_lost && lost_s_ >= params_.lost_after_s) {
    verdict_ = {
        SafetyStop::kLocalizationLost,
        absl::StrFormat("localization lost for %.1f s%s: the robot stopped", lost_s_,
                        lost_reason.empty() ? std::string()
                                            : absl::StrCat(" (", std::string(lost_reason), ")"))};
  }
  return verdict_;
}

}  // namespace fleetnav::agent
