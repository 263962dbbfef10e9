#include "fleetnav/server/http/dashboard_json.hpp"

#include <cmath>
#include <string>

#include "absl/strings/escaping.h"
#include "fleetnav/core/map_io.hpp"
#include "fleetnav/proto/job_convert.hpp"

namespace fleetnav::server::http {
namespace {

nlohmann::json PointJson(const Eigen::Vector2d& p) { return {p.x(), p.y()}; }

}  // namespace

CovarianceEllipse EllipseOf(const std::array<double, 9>& covariance) {
  const double a = covariance[0], b = covariance[1], d = covariance[4];
  const double mean = 0.5 * (a + d);
  const double spread = std::sqrt(std::max(0.0, 0.25 * (a - d) * (a - d) + b * b));
  CovarianceEllipse ellipse;
  ellipse.major_m = std::sqrt(std::max(0.0, mean + spread));
  ellipse.minor_m = std::sqrt(std::max(0.0, mean - spread));
  ellipse.angle_rad = 0.5 * std::atan2(2.0 * b, a - d);
  return ellipse;
}

nlohmann::json FleetStateJson(const std::vector<RobotRecord>& robots, const std::vector<Job>& jobs,
                              const std::vector<RobotStop>& stops, int64_t server_unix_ms) {
  nlohmann::json robot_list = nlohmann::json::array();
  for (const RobotRecord& robot : robots) {
    nlohmann::json entry = {{"robot_id", robot.identity.robot_id},
                            {"kind", robot.identity.model.kind_name},
                            {"connection", std::string(ConnectionStateName(robot.connection))},
                            {"job_id", robot.current_job_id},
                            {"traffic_wait", robot.traffic_wait},
                            {"traffic_held_s", robot.traffic_held_s}};
    if (robot.last_telemetry) {
      const Telemetry& t = *robot.last_telemetry;
      const CovarianceEllipse ellipse = EllipseOf(t.covariance);
      entry["pose"] = {{"x_m", t.pose_in_map.x_m()},
                       {"y_m", t.pose_in_map.y_m()},
                       {"yaw_rad", t.pose_in_map.yaw_rad()}};
      entry["ellipse"] = {{"major_m", ellipse.major_m},
                          {"minor_m", ellipse.minor_m},
                          {"angle_rad", ellipse.angle_rad}};
      entry["mode"] = std::string(NavigationModeName(t.mode));
      entry["battery"] = t.battery_fraction;
      entry["speed_mps"] = std::hypot(t.velocity.vx_mps, t.velocity.vy_mps);
      entry["confidence"] = t.localization_confidence;
    }
    robot_list.push_back(std::move(entry));
  }
  nlohmann::json job_list = nlohmann::json::array();
  for (const Job& job : jobs) {
    job_list.push_back({{"job_id", job.job_id},
                        {"state", std::string(JobStateName(job.state))},
                        {"progress", job.progress_fraction},
                        {"robot_id", job.assigned_robot_id},
                        {"route", job.route_name},
                        {"map_id", job.map_id},
                        {"reason", job.reason}});
  }
  return {{"server_unix_ms", server_unix_ms},
          {"robots", robot_list},
          {"jobs", job_list},
          {"stops", StopsJson(stops)}};
}

namespace {

nlohmann::json PolygonJson(const Polygon2& polygon) {
  nlohmann::json points = nlohmann::json::array();
  for (const Eigen::Vector2d& vertex : polygon) points.push_back(PointJson(vertex));
  return points;
}

}  // namespace

nlohmann::json StopsJson(const std::vector<RobotStop>& stops) {
  nlohmann::json list = nlohmann::json::array();
  for (const RobotStop& stop : stops) {
    list.push_back({{"map_id", stop.map_id},
                    {"zone", stop.zone},
                    {"reason", stop.reason},
                    {"created_unix_ms", stop.created_unix_ms},
                    {"polygon", PolygonJson(stop.polygon_in_map)}});
  }
  return list;
}

nlohmann::json ZonesJson(uint32_t version, const ZoneSet* zones) {
  nlohmann::json list = nlohmann::json::array();
  if (zones != nullptr) {
    for (const Zone& zone : zones->zones) {
      list.push_back({{"name", zone.name},
                      {"kind", std::string(ZoneKindName(zone.kind))},
                      {"polygon", PolygonJson(zone.polygon_in_map)},
                      {"speed_limit_mps", zone.speed_limit_mps},
                      {"capacity", zone.capacity}});
    }
  }
  return {{"version", version}, {"zones", list}};
}

nlohmann::json MapJson(const std::string& map_id, uint32_t version, const OccupancyGrid& grid) {
  std::string greys;  // top row first, one byte per cell
  greys.reserve(static_cast<size_t>(grid.width()) * grid.height());
  for (int y = grid.height() - 1; y >= 0; --y) {
    for (int x = 0; x < grid.width(); ++x) {
      greys.push_back(static_cast<char>(MapServerGrey(grid.Value({x, y}))));
    }
  }
  return {{"map_id", map_id},
          {"version", version},
          {"width", grid.width()},
          {"height", grid.height()},
          {"resolution_m", grid.resolution_m()},
          {"origin", {grid.origin().x_m(), grid.origin().y_m(), grid.origin().yaw_rad()}},
          {"cells", absl::Base64Escape(greys)}};
}

nlohmann::json SiteJson(const MarkerSet* markers, const std::vector<Route>& routes) {
  nlohmann::json marker_list = nlohmann::json::array();
  if (markers != nullptr) {
    for (const StripeMarker& marker : markers->markers) {
      marker_list.push_back({{"id", marker.id},
                             {"x_m", marker.position_m.x()},
                             {"y_m", marker.position_m.y()},
                             {"yaw_rad", marker.yaw_rad},
                             {"length_m", marker.length_m},
                             {"kind", std::string(MarkerKindName(marker.kind))},
                             {"stripe_id", marker.stripe_id}});
    }
  }
  nlohmann::json route_list = nlohmann::json::array();
  for (const Route& route : routes) {
    nlohmann::json legs = nlohmann::json::array();
    nlohmann::json stripes = nlohmann::json::array();
    for (const RouteAction& action : route.actions) {
      if (const auto* nav = std::get_if<FreeNavigationAction>(&action.params)) {
        nlohmann::json points = nlohmann::json::array();
        for (const Eigen::Vector2d& waypoint : nav->waypoints_m)
          points.push_back(PointJson(waypoint));
        points.push_back(PointJson(nav->goal.translation()));
        legs.push_back(std::move(points));
      } else if (const auto* stripe = std::get_if<StripeNavigationAction>(&action.params)) {
        stripes.push_back(stripe->stripe_id);
      }
    }
    route_list.push_back({{"name", route.name}, {"legs", legs}, {"stripes", stripes}});
  }
  return {{"markers", marker_list}, {"routes", route_list}};
}

nlohmann::json JobEventsJson(const std::vector<JobEvent>& events) {
  nlohmann::json list = nlohmann::json::array();
  for (const JobEvent& event : events) {
    list.push_back({{"sequence", event.sequence},
                    {"type", v1::JobEventType_Name(ToProto(event).type())},
                    {"unix_ms", event.unix_ms},
                    {"robot_id", event.robot_id},
                    {"state", std::string(JobStateName(event.state))},
                    {"progress", event.progress_fraction},
                    {"reason", event.reason}});
  }
  return list;
}

}  // namespace fleetnav::server::http
