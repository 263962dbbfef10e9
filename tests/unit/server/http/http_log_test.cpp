// The dashboard's JSON documents and fleetnavd's log lines, without a network.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <spdlog/details/log_msg.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/server/http/dashboard_json.hpp"
#include "fleetnav/server/log/log_format.hpp"

namespace fleetnav::server {
namespace {

using ::testing::HasSubstr;

TEST(DashboardJsonTest, TheEllipseHasTheCovariancesAxes) {
  // Variances 0.04 along a line at 30°, 0.01 across it.
  const double angle = kPi / 6, c = std::cos(angle), s = std::sin(angle);
  const double major = 0.04, minor = 0.01;
  std::array<double, 9> covariance{};
  covariance[0] = major * c * c + minor * s * s;
  covariance[1] = covariance[3] = (major - minor) * c * s;
  covariance[4] = major * s * s + minor * c * c;
  const http::CovarianceEllipse ellipse = http::EllipseOf(covariance);
  EXPECT_NEAR(ellipse.major_m, 0.2, 1e-9);
  EXPECT_NEAR(ellipse.minor_m, 0.1, 1e-9);
  EXPECT_NEAR(ellipse.angle_rad, angle, 1e-9);
  EXPECT_EQ(http::EllipseOf({}).major_m, 0.0);
}

TEST(DashboardJsonTest, TheMapIsSentTopRowFirstInMapServerGreys) {
  // 3 x 2 cells: the bottom row free, occupied, unknown; the top row all free.
  OccupancyGrid grid = *OccupancyGrid::Filled(3, 2, 0.5, Pose2(1.0, 2.0, 0.0), 0);
  grid.SetValue({1, 0}, 100);
  grid.SetValue({2, 0}, -1);
  const nlohmann::json map = http::MapJson("barn", 4, grid);
  EXPECT_EQ(map["width"], 3);
  EXPECT_EQ(map["height"], 2);
  EXPECT_EQ(map["version"], 4);
  EXPECT_EQ(map["origin"][0], 1.0);
  // Bytes FE FE FE FE 00 CD in base64.
  EXPECT_EQ(map["cells"], "/v7+/gDN");
}

TEST(DashboardJsonTest, RobotsAndJobsCarryWhatTheDashboardShows) {
  RobotRecord robot;
  robot.identity.robot_id = "lely1";
  robot.identity.model.kind_name = "lely-vector";
  robot.connection = ConnectionState::kStale;
  robot.traffic_wait = "lely2 in segment 3";
  Telemetry telemetry;
  telemetry.pose_in_map = Pose2(1.5, -2.0, 0.25);
  telemetry.battery_fraction = 0.8;
  telemetry.mode = NavigationMode::kFenceReactive;
  robot.last_telemetry = telemetry;
  RobotRecord silent;
  silent.identity.robot_id = "lely2";
  Job job;
  job.job_id = "job-000007";
  job.state = JobState::kRunning;
  job.progress_fraction = 0.4;
  job.assigned_robot_id = "lely1";
  RobotStop stop;
  stop.map_id = "barn";
  stop.zone = "pen";
  stop.reason = "cleaning";
  stop.polygon_in_map = {{0, 0}, {2, 0}, {2, 1}};
  const nlohmann::json state = http::FleetStateJson({robot, silent}, {job}, {stop}, 1234);
  ASSERT_EQ(state["robots"].size(), 2u);
  EXPECT_EQ(state["robots"][0]["connection"], "stale");
  EXPECT_EQ(state["robots"][0]["pose"]["x_m"], 1.5);
  EXPECT_EQ(state["robots"][0]["battery"], 0.8);
  EXPECT_EQ(state["robots"][0]["traffic_wait"], "lely2 in segment 3");
  EXPECT_FALSE(state["robots"][1].contains("pose"));  // no telemetry yet
  EXPECT_EQ(state["jobs"][0]["state"], "running");
  EXPECT_EQ(state["jobs"][0]["progress"], 0.4);
  EXPECT_EQ(state["server_unix_ms"], 1234);
  ASSERT_EQ(state["stops"].size(), 1u);
  EXPECT_EQ(state["stops"][0]["zone"], "pen");
  EXPECT_EQ(state["stops"][0]["reason"], "cleaning");
  EXPECT_EQ(state["stops"][0]["polygon"][1], nlohmann::json({2.0, 0.0}));
}

TEST(DashboardJsonTest, ZonesCarryTheirKindOutlineAndRule) {
  ZoneSet zones;
  zones.zones.push_back({"pen", ZoneKind::kNoGo, {{0, 0}, {2, 0}, {2, 1}}, 0.0, 1});
  zones.zones.push_back({"door", ZoneKind::kSpeedLimit, {{4, 0}, {5, 0}, {5, 1}}, 0.3, 1});
  const nlohmann::json json = http::ZonesJson(7, &zones);
  EXPECT_EQ(json["version"], 7);
  ASSERT_EQ(json["zones"].size(), 2u);
  EXPECT_EQ(json["zones"][0]["kind"], "no_go");
  EXPECT_EQ(json["zones"][1]["kind"], "speed_limit");
  EXPECT_EQ(json["zones"][1]["speed_limit_mps"], 0.3);
  EXPECT_EQ(json["zones"][0]["polygon"].size(), 3u);
  EXPECT_EQ(http::ZonesJson(0, nullptr)["zones"].size(), 0u);
}

spdlog::details::log_msg Message(const std::string& payload) {
  return spdlog::details::log_msg(spdlog::source_loc{}, "fleetnavd", spdlog::level::warn, payload);
}

nlohmann::json FormatJson(const std::string& payload) {
  log::JsonLogFormatter formatter;
  spdlog::memory_buf_t out;
  formatter.format(Message(payload), out);
  const std::string line(out.data(), out.size());
  EXPECT_EQ(line.back(), '\n');
  EXPECT_EQ(line.find('\n'), line.size() - 1);  // one line
  return nlohmann::json::parse(line);
}

TEST(LogFormatTest, EveryLineIsOneJsonObjectWithItsFields) {
  const nlohmann::json plain = FormatJson("a \"quoted\"\nmessage\twith\\ escapes");
  EXPECT_EQ(plain["msg"], "a \"quoted\"\nmessage\twith\\ escapes");
  EXPECT_EQ(plain["level"], "warning");
  EXPECT_THAT(plain["ts"].get<std::string>(),
              ::testing::MatchesRegex("[0-9]{4}-[0-9]{2}-[0-9]{2}T[0-9:]{8}\\.[0-9]{3}Z"));
  Job job;
  job.job_id = "job-000003";
  job.route_name = "feed";
  JobEvent event;
  event.type = JobEventType::kFailed;
  event.state = JobState::kFailed;
  event.robot_id = "lely1";
  event.reason = "bumper pressed";
  const std::optional<log::LogFields> line = log::JobTransitionLine(job, event);
  ASSERT_TRUE(line.has_value());
  const nlohmann::json fielded = FormatJson(log::FormatLogPayload(log::LogFormat::kJson, *line));
  EXPECT_EQ(fielded["job_id"], "job-000003");
  EXPECT_EQ(fielded["robot_id"], "lely1");
  EXPECT_EQ(fielded["state"], "failed");
  EXPECT_EQ(fielded["reason"], "bumper pressed");
  EXPECT_EQ(fielded["msg"], "job job-000003 failed (robot lely1): bumper pressed");
  EXPECT_EQ(log::FormatLogPayload(log::LogFormat::kText, *line),
            "job job-000003 failed (robot lely1): bumper pressed event=job_transition "
            "job_id=job-000003 state=failed robot_id=lely1 route=feed reason=bumper pressed");
}

TEST(LogFormatTest, OnlyStateChangesMakeATransitionLine) {
  Job job;
  job.job_id = "job-1";
  JobEvent progress;
  progress.type = JobEventType::kProgress;
  EXPECT_FALSE(log::JobTransitionLine(job, progress).has_value());
  JobEvent assigned;
  assigned.type = JobEventType::kAssigned;
  assigned.state = JobState::kAssigned;
  assigned.robot_id = "r2";
  EXPECT_THAT(log::JobTransitionLine(job, assigned)->message, HasSubstr("assigned (robot r2)"));
  EXPECT_EQ(log::ParseLogFormat("yaml").status().code(), absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace fleetnav::server
