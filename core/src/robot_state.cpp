#include "fleetnav/core/robot_state.hpp"

namespace fleetnav {

std::string_view ConnectionStateName(ConnectionState state) {
  switch (state) {
    case ConnectionState::kOnline:
      return "online";
    case ConnectionState::kStale:
      return "stale";
    case ConnectionState::kOffline:
      break;
  }
  return "offline";
}

std::string_view NavigationModeName(NavigationMode mode) {
  switch (mode) {
    case NavigationMode::kIdle:
      return "idle";
    case NavigationMode::kTurn:
      return "turn";
    case NavigationMode::kStraight:
      return "straight";
    case NavigationMode::kFreeNavigation:
      return "free_navigation";
    case NavigationMode::kFenceReactive:
      return "fence_reactive";
    case NavigationMode::kFenceMapBased:
      return "fence_map_based";
    case NavigationMode::kStripeReactive:
      return "stripe_reactive";
    case NavigationMode::kStripeMapBased:
      return "stripe_map_based";
    case NavigationMode::kDocking:
      return "docking";
    case NavigationMode::kPaused:
      return "paused";
    case NavigationMode::kFault:
      return "fault";
  }
  return "unknown";
}

}  // namespace fleetnav
