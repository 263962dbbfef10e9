#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "fleetnav/core/route.hpp"

namespace fleetnav::server {

/// One capability a job needs (an action type name: "turn", "free_navigation", …) and the first
/// of its actions that needs it, so that a refusal or a queued job's reason can point at the
/// action an operator has to change: "actions[2] (turn)". A go-to-goal job's one need has
/// first_action -1 and reads "the goal (free_navigation)".
struct NeededCapability {
  std::string capability;
  int first_action = -1;
  /// "actions[2] (turn)", or "the goal (free_navigation)" for a go-to-goal job.
  std::string Describe() const;
};

/// What a route's actions need, each capability once, in the order the route first uses them.
std::vector<NeededCapability> NeedsOfRoute(const Route& route);
/// What a go-to-goal job needs: free navigation.
std::vector<NeededCapability> NeedsOfGoal();
/// The first need that `has` denies, in the route's order; nullopt when every need is met.
std::optional<NeededCapability> FirstUnmet(const std::vector<NeededCapability>& needs,
                                           const std::function<bool(const std::string&)>& has);

}  // namespace fleetnav::server
