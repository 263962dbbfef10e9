#include "fleetnav/core/robot_stop.hpp"

#include "absl/strings/str_cat.h"

namespace fleetnav {

std::string RobotStop::Describe() const {
  if (whole_fleet()) return "the whole fleet";
  return absl::StrCat("zone '", zone, "' of map '", map_id, "'");
}

const RobotStop* ApplyingStop(const std::vector<RobotStop>& stops, const std::string& map_id,
                              const Eigen::Vector2d& center, double reach_m) {
  for (const RobotStop& stop : stops) {
    if (stop.whole_fleet()) return &stop;
    if (stop.map_id == map_id && stop.polygon_in_map.size() >= 3 &&
        DiscTouchesPolygon(stop.polygon_in_map, center, reach_m)) {
      return &stop;
    }
  }
  return nullptr;
}

}  // namespace fleetnav
