#include "fleetnav/server/jobs/job_needs.hpp"

#include <algorithm>

#include "absl/strings/str_cat.h"

namespace fleetnav::server {

std::string NeededCapability::Describe() const {
  if (first_action < 0) return absl::StrCat("the goal (", capability, ")");
  return absl::StrCat("actions[", first_action, "] (", capability, ")");
}

std::vector<NeededCapability> NeedsOfRoute(const Route& route) {
  std::vector<NeededCapability> needs;
  for (size_t i = 0; i < route.actions.size(); ++i) {
    const std::string capability(ActionTypeName(route.actions[i].params));
    const bool known = std::any_of(needs.begin(), needs.end(), [&](const NeededCapability& n) {
      return n.capability == capability;
    });
    if (!known) needs.push_back({capability, static_cast<int>(i)});
  }
  return needs;
}

std::vector<NeededCapability> NeedsOfGoal() { return {{"free_navigation", -1}}; }

std::optional<NeededCapability> FirstUnmet(const std::vector<NeededCapability>& needs,
                                           const std::function<bool(const std::string&)>& has) {
  for (const NeededCapability& need : needs) {
    if (!has(need.capability)) return need;
  }
  return std::nullopt;
}

}  // namespace fleetnav::server
