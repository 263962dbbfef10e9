#include "fleetnav/core/sim_truth.hpp"

#include "absl/strings/str_cat.h"

namespace fleetnav {

std::string_view FaultTypeName(FaultType type) {
  switch (type) {
    case FaultType::kHideUltrasonicRegion:
      return "hide_ultrasonic";
    case FaultType::kRemoveFenceSegment:
      return "remove_fence";
    case FaultType::kRemoveStripeSegment:
      return "remove_stripe";
    case FaultType::kWheelSlipRegion:
      return "wheel_slip";
    case FaultType::kSensorDropout:
      return "sensor_dropout";
    case FaultType::kSlowDown:
      return "slow_down";
  }
  return "hide_ultrasonic";
}

absl::StatusOr<FaultType> FaultTypeByName(std::string_view name) {
  for (FaultType type : {FaultType::kHideUltrasonicRegion, FaultType::kRemoveFenceSegment,
                         FaultType::kRemoveStripeSegment, FaultType::kWheelSlipRegion,
                         FaultType::kSensorDropout, FaultType::kSlowDown}) {
    if (FaultTypeName(type) == name) return type;
  }
  return absl::InvalidArgumentError(absl::StrCat(
      "unknown fault type '", std::string(name),
      "' (known: hide_ultrasonic, remove_fence, remove_stripe, wheel_slip, sensor_dropout, "
      "slow_down)"));
}

}  // namespace fleetnav
