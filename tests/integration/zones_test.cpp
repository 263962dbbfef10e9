// Zones over real loopback gRPC against a real SQLite file (issue 39): PutZones, GetZones,
// ListZones, DeleteZones with their refusals (the field named, nothing stored), zones kept
// through a restart, no-go zones refusing the waypoints and goals of routes and jobs, and
// fleetnavctl's `zones` commands.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "fleet_fixture.hpp"
#include "fleetnav/proto/geometry_convert.hpp"
#include "fleetnav/proto/telemetry_convert.hpp"
#include "fleetnav/proto/zone_convert.hpp"
#include "fleetnav/scenario/child_process.hpp"
#include "fleetnav/v1/agent_service.grpc.pb.h"

namespace fleetnav {
namespace {

using ::testing::HasSubstr;

Polygon2 Rectangle(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

class ZonesTest : public testing::FleetServerFixture {
 protected:
  /// A free 10 m × 6 m map "hall" (0.1 m cells, origin at 0, 0).
  void PutHall() {
    absl::StatusOr<OccupancyGrid> grid = OccupancyGrid::Filled(100, 60, 0.1, Pose2(), 0);
    ASSERT_TRUE(grid.ok());
    grpc::ClientContext context;
    v1::PutMapRequest request;
    request.set_map_id("hall");
    *request.mutable_grid() = ToProto(*grid);
    v1::PutMapResponse response;
    ASSERT_TRUE(fleet_->PutMap(&context, request, &response).ok());
  }

  static ZoneSet HallZones() {
    ZoneSet zones;
    zones.map_id = "hall";
    zones.zones.push_back({"pen", ZoneKind::kNoGo, Rectangle(2, 2, 4, 4), 0.0, 1});
    zones.zones.push_back({"checkout", ZoneKind::kSpeedLimit, Rectangle(6, 0.5, 9, 2), 0.3, 1});
    zones.zones.push_back({"door", ZoneKind::kOneAtATime, Rectangle(8, 4, 9, 5.5), 0.0, 1});
    return zones;
  }

  grpc::Status PutZones(const v1::ZoneSet& zones, v1::PutZonesResponse* response) {
    grpc::ClientContext context;
    v1::PutZonesRequest request;
    *request.mutable_zone_set() = zones;
    return fleet_->PutZones(&context, request, response);
  }

  grpc::Status GetZones(const std::string& map_id, uint32_t version, v1::GetZonesResponse* out) {
    grpc::ClientContext context;
    v1::GetZonesRequest request;
    request.set_map_id(map_id);
    request.set_version(version);
    return fleet_->GetZones(&context, request, out);
  }

  v1::ListZonesResponse ListZones() {
    grpc::ClientContext context;
    v1::ListZonesResponse response;
    EXPECT_TRUE(fleet_->ListZones(&context, {}, &response).ok());
    return response;
  }

  void ExpectRefused(const v1::ZoneSet& zones, grpc::StatusCode code, const std::string& needle) {
    v1::PutZonesResponse response;
    const grpc::Status status = PutZones(zones, &response);
    EXPECT_EQ(status.error_code(), code) << status.error_message();
    EXPECT_THAT(status.error_message(), HasSubstr(needle));
  }
};

TEST_F(ZonesTest, ZonesAreVersionedListedReadAndDeleted) {
  PutHall();
  v1::PutZonesResponse put;
  ASSERT_TRUE(PutZones(ToProto(HallZones()), &put).ok());
  EXPECT_EQ(put.map_id(), "hall");
  EXPECT_EQ(put.version(), 1u);
  // The same zones again are the version that holds them.
  ASSERT_TRUE(PutZones(ToProto(HallZones()), &put).ok());
  EXPECT_EQ(put.version(), 1u);
  ZoneSet fewer = HallZones();
  fewer.zones.pop_back();
  ASSERT_TRUE(PutZones(ToProto(fewer), &put).ok());
  EXPECT_EQ(put.version(), 2u);

  v1::GetZonesResponse got;
  ASSERT_TRUE(GetZones("hall", 0, &got).ok());
  EXPECT_EQ(got.version(), 2u);
  EXPECT_EQ(got.zone_set().zones_size(), 2);
  ASSERT_TRUE(GetZones("hall", 1, &got).ok());
  absl::StatusOr<ZoneSet> first = FromProto(got.zone_set());
  ASSERT_TRUE(first.ok()) << first.status();
  EXPECT_EQ(ZoneSetToYaml(*first), ZoneSetToYaml(HallZones()));
  EXPECT_EQ(GetZones("hall", 3, &got).error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_EQ(GetZones("yard", 0, &got).error_code(), grpc::StatusCode::NOT_FOUND);

  const v1::ListZonesResponse listed = ListZones();
  ASSERT_EQ(listed.zone_sets_size(), 1);
  EXPECT_EQ(listed.zone_sets(0).map_id(), "hall");
  EXPECT_EQ(listed.zone_sets(0).version(), 2u);
  EXPECT_EQ(listed.zone_sets(0).no_go_zones(), 1u);
  EXPECT_EQ(listed.zone_sets(0).speed_limit_zones(), 1u);
  EXPECT_EQ(listed.zone_sets(0).one_at_a_time_zones(), 0u);

  // Kept through a restart of the server.
  StopServer();
  StartServer();
  ASSERT_TRUE(GetZones("hall", 0, &got).ok());
  EXPECT_EQ(got.version(), 2u);

  grpc::ClientContext context;
  v1::DeleteZonesRequest remove;
  remove.set_map_id("hall");
  v1::DeleteZonesResponse removed;
  ASSERT_TRUE(fleet_->DeleteZones(&context, remove, &removed).ok());
  EXPECT_EQ(GetZones("hall", 0, &got).error_code(), grpc::StatusCode::NOT_FOUND);
  grpc::ClientContext again;
  EXPECT_EQ(fleet_->DeleteZones(&again, remove, &removed).error_code(),
            grpc::StatusCode::NOT_FOUND);
  EXPECT_EQ(ListZones().zone_sets_size(), 0);
}

TEST_F(ZonesTest, BadZonesAreRefusedNamingTheFieldAndNothingIsStored) {
  PutHall();
  ZoneSet bow_tie = HallZones();
  bow_tie.zones[0].polygon_in_map = {{2, 2}, {4, 4}, {4, 2}, {2, 4}};
  ExpectRefused(ToProto(bow_tie), grpc::StatusCode::INVALID_ARGUMENT,
                "zones[0].polygon: edges 0-1 and 2-3 cross");
  ZoneSet flat = HallZones();
  flat.zones[1].polygon_in_map = {{6, 1}, {7, 1}, {8, 1}};
  ExpectRefused(ToProto(flat), grpc::StatusCode::INVALID_ARGUMENT, "zones[1].polygon");
  ZoneSet off_map = HallZones();
  off_map.zones[2].polygon_in_map = Rectangle(8, 4, 11, 5.5);
  ExpectRefused(ToProto(off_map), grpc::StatusCode::INVALID_ARGUMENT,
                "zones[2].polygon[1]: (11, 4) is off the map");
  ZoneSet no_speed = HallZones();
  no_speed.zones[1].speed_limit_mps = -0.2;
  ExpectRefused(ToProto(no_speed), grpc::StatusCode::INVALID_ARGUMENT, "zones[1].speed_limit");
  v1::ZoneSet unspecified = ToProto(HallZones());
  unspecified.mutable_zones(0)->set_kind(v1::ZONE_KIND_UNSPECIFIED);
  ExpectRefused(unspecified, grpc::StatusCode::INVALID_ARGUMENT, "zones[0].kind");
  ZoneSet twice = HallZones();
  twice.zones[1].name = "pen";
  ExpectRefused(ToProto(twice), grpc::StatusCode::INVALID_ARGUMENT, "zones[1].name");
  ZoneSet unknown_map = HallZones();
  unknown_map.map_id = "yard";
  ExpectRefused(ToProto(unknown_map), grpc::StatusCode::NOT_FOUND, "yard");
  ZoneSet bad_id = HallZones();
  bad_id.map_id = "Hall!";
  ExpectRefused(ToProto(bad_id), grpc::StatusCode::INVALID_ARGUMENT, "map_id");
  EXPECT_EQ(ListZones().zone_sets_size(), 0);
}

TEST_F(ZonesTest, NoGoZonesRefuseTheWaypointsAndGoalsOfRoutesAndJobs) {
  PutHall();
  Route through_pen;
  through_pen.name = "through-pen";
  through_pen.map_id = "hall";
  FreeNavigationAction nav;
  nav.waypoints_m = {{1.0, 1.0}};
  nav.goal = Pose2(3.0, 3.0, 0.0);
  through_pen.actions.push_back(RouteAction{nav, {}});
  // Stored while the hall has no zones.
  ASSERT_TRUE(PutRoute(through_pen).ok());
  v1::PutZonesResponse put;
  ASSERT_TRUE(PutZones(ToProto(HallZones()), &put).ok());

  through_pen.name = "through-pen-2";
  const grpc::Status refused = PutRoute(through_pen);
  EXPECT_EQ(refused.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(
      refused.error_message(),
      HasSubstr("actions[0] (free_navigation): goal (3.00, 3.00) lies in no-go zone 'pen'"));
  // The route stored before the zone cannot be run now.
  v1::SubmitJobResponse job;
  const grpc::Status stale = Submit("through-pen", "key-1", &job);
  EXPECT_EQ(stale.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(stale.error_message(), HasSubstr("no-go zone 'pen'"));
  // Nor can a goal in the pen.
  grpc::ClientContext context;
  v1::SubmitJobRequest goal;
  goal.mutable_goal()->set_map_id("hall");
  *goal.mutable_goal()->mutable_goal() = ToProto(Pose2(2.5, 3.5, 0.0));
  const grpc::Status goal_refused = fleet_->SubmitJob(&context, goal, &job);
  EXPECT_EQ(goal_refused.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(goal_refused.error_message(), HasSubstr("goal.goal (2.50, 3.50) lies in no-go"));
  grpc::ClientContext listing;
  v1::ListJobsResponse jobs;
  ASSERT_TRUE(fleet_->ListJobs(&listing, {}, &jobs).ok());
  EXPECT_EQ(jobs.jobs_size(), 0);
  // Outside the pen, the same goal is taken.
  grpc::ClientContext outside;
  *goal.mutable_goal()->mutable_goal() = ToProto(Pose2(5.0, 3.0, 0.0));
  EXPECT_TRUE(fleet_->SubmitJob(&outside, goal, &job).ok());
}

TEST_F(ZonesTest, PlanPathsKeepsOutOfNoGoZones) {
  PutHall();
  // A platform from the west of the pen to its east (in the middle of 1 m planning cells): the
  // straight way crosses it.
  const auto plan = [&] {
    grpc::ClientContext context;
    v1::PlanPathsRequest request;
    request.set_map_id("hall");
    request.set_time_limit_s(10.0);
    v1::PlanPathsRequest::Agent* agent = request.add_agents();
    agent->set_robot_id("omni1");
    agent->set_kind_name("mecanum-platform");
    agent->mutable_start()->set_x_m(0.5);
    agent->mutable_start()->set_y_m(3.0);
    agent->mutable_goal()->set_x_m(5.5);
    agent->mutable_goal()->set_y_m(3.0);
    v1::PlanPathsResponse response;
    const grpc::Status status = fleet_->PlanPaths(&context, request, &response);
    EXPECT_TRUE(status.ok()) << status.error_message();
    EXPECT_EQ(response.paths_size(), 1);
    return response;
  };
  const Polygon2 pen = Rectangle(2, 2, 4, 4);
  const auto poses_in_pen = [&](const v1::PlanPathsResponse& response) {
    int inside = 0;
    for (const auto& pose : response.paths(0).poses()) {
      if (PolygonContains(pen, {pose.pose().x_m(), pose.pose().y_m()})) ++inside;
    }
    return inside;
  };
  const v1::PlanPathsResponse straight = plan();
  ASSERT_EQ(straight.paths_size(), 1);
  EXPECT_GT(poses_in_pen(straight), 0);  // without zones it crosses the pen
  v1::PutZonesResponse put;
  ASSERT_TRUE(PutZones(ToProto(HallZones()), &put).ok());
  const v1::PlanPathsResponse round = plan();
  ASSERT_EQ(round.paths_size(), 1);
  EXPECT_EQ(poses_in_pen(round), 0);
  const auto& end = round.paths(0).poses(round.paths(0).poses_size() - 1).pose();
  EXPECT_NEAR(end.x_m(), 5.5, 1e-9);
}

TEST_F(ZonesTest, FleetnavctlPutsGetsListsAndDeletesZones) {
  PutHall();
  const auto run = [&](std::vector<std::string> args) {
    args.insert(args.begin(), FLEETNAV_FLEETNAVCTL_PATH);
    args.push_back("--server=127.0.0.1:" + std::to_string(port_));
    const std::string base = testing::UniqueTempPath("zones-ctl");
    scenario::ChildProcess child(args, base + ".out", base + ".err");
    EXPECT_TRUE(child.started());
    const int code = child.Wait(30.0).value_or(-1);
    return std::tuple<int, std::string, std::string>{code, child.Stdout(), child.Stderr()};
  };
  const std::string path = testing::UniqueTempPath("zones") + ".yaml";
  std::ofstream(path) << ZoneSetToYaml(HallZones());
  auto [put_code, put_out, put_err] = run({"zones", "put", path, "--json"});
  ASSERT_EQ(put_code, 0) << put_err;
  EXPECT_EQ(nlohmann::json::parse(put_out)["version"], 1);
  EXPECT_EQ(nlohmann::json::parse(put_out)["zones"], 3);

  auto [get_code, get_out, get_err] = run({"zones", "get", "--map", "hall", "--json"});
  ASSERT_EQ(get_code, 0) << get_err;
  const nlohmann::json got = nlohmann::json::parse(get_out);
  EXPECT_EQ(got["zones"][1]["kind"], "speed_limit");
  EXPECT_DOUBLE_EQ(got["zones"][1]["speed_limit_mps"].get<double>(), 0.3);
  EXPECT_EQ(got["zones"][0]["polygon"][2], nlohmann::json::array({4.0, 4.0}));

  auto [yaml_code, yaml_out, yaml_err] = run({"zones", "get", "--map", "hall"});
  ASSERT_EQ(yaml_code, 0) << yaml_err;
  absl::StatusOr<ZoneSet> parsed = ParseZoneSetYaml(yaml_out);
  ASSERT_TRUE(parsed.ok()) << parsed.status();
  EXPECT_EQ(parsed->zones.size(), 3u);

  auto [list_code, list_out, list_err] = run({"zones", "list", "--json"});
  ASSERT_EQ(list_code, 0) << list_err;
  EXPECT_EQ(nlohmann::json::parse(list_out)[0]["one_at_a_time"], 1);

  // A self-intersecting zone in the file is refused before anything is sent (exit 4).
  const std::string bad = testing::UniqueTempPath("bad-zones") + ".yaml";
  std::ofstream(bad) << "map: hall\nzones:\n  - {name: x, kind: no_go, polygon: "
                        "[[0,0],[2,2],[2,0],[0,2]]}\n";
  auto [bad_code, bad_out, bad_err] = run({"zones", "put", bad});
  EXPECT_EQ(bad_code, 4);
  EXPECT_THAT(bad_err, HasSubstr("zones[0].polygon: edges 0-1 and 2-3 cross"));

  auto [delete_code, delete_out, delete_err] = run({"zones", "delete", "--map", "hall", "--json"});
  ASSERT_EQ(delete_code, 0) << delete_err;
  EXPECT_EQ(nlohmann::json::parse(delete_out)["deleted_zones_of"], "hall");
  EXPECT_EQ(std::get<0>(run({"zones", "get", "--map", "hall"})), 3);
}

TEST_F(ZonesTest, StopsAreCheckedStoredKeptThroughARestartAndCleared) {
  PutHall();
  v1::PutZonesResponse put;
  ASSERT_TRUE(PutZones(ToProto(HallZones()), &put).ok());
  const auto stop = [&](bool whole_fleet, const std::string& map, const std::string& zone,
                        v1::StopRobotsResponse* response) {
    grpc::ClientContext context;
    v1::StopRobotsRequest request;
    request.mutable_scope()->set_whole_fleet(whole_fleet);
    request.mutable_scope()->set_map_id(map);
    request.mutable_scope()->set_zone(zone);
    request.set_reason("cleaning");
    return fleet_->StopRobots(&context, request, response);
  };
  const auto list = [&] {
    grpc::ClientContext context;
    v1::ListStopsResponse response;
    EXPECT_TRUE(fleet_->ListStops(&context, {}, &response).ok());
    return response;
  };
  v1::StopRobotsResponse stopped;
  // Bad scopes, unknown zones: nothing stored.
  EXPECT_EQ(stop(false, "", "", &stopped).error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(stop(true, "", "pen", &stopped).error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  const grpc::Status unknown = stop(false, "", "kitchen", &stopped);
  EXPECT_EQ(unknown.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_THAT(unknown.error_message(), HasSubstr("no map has a zone named 'kitchen'"));
  EXPECT_EQ(stop(false, "hall", "kitchen", &stopped).error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_EQ(list().stops_size(), 0);
  // A zone found by its name alone, with its outline; the same scope again is refused.
  ASSERT_TRUE(stop(false, "", "door", &stopped).ok());
  EXPECT_EQ(stopped.stop().map_id(), "hall");
  EXPECT_EQ(stopped.stop().polygon_size(), 4);
  EXPECT_EQ(stop(false, "hall", "door", &stopped).error_code(), grpc::StatusCode::ALREADY_EXISTS);
  ASSERT_TRUE(stop(true, "", "", &stopped).ok());
  ASSERT_EQ(list().stops_size(), 2);
  {
    // A robot that connects now hears both in its welcome.
    std::unique_ptr<v1::AgentService::Stub> agents = v1::AgentService::NewStub(channel_);
    grpc::ClientContext context;
    std::unique_ptr<grpc::ClientReaderWriter<v1::AgentMessage, v1::ServerMessage>> agent =
        agents->Connect(&context);
    v1::AgentMessage hello;
    *hello.mutable_hello() = ToProto(RobotIdentity{"omni1", MecanumPlatformModel(), {}, "t"});
    ASSERT_TRUE(agent->Write(hello));
    v1::ServerMessage welcome;
    ASSERT_TRUE(agent->Read(&welcome));
    ASSERT_TRUE(welcome.has_welcome());
    ASSERT_EQ(welcome.welcome().stops_size(), 2);
    EXPECT_EQ(welcome.welcome().stops(0).zone(), "door");
    EXPECT_EQ(welcome.welcome().stops(1).zone(), "");
    agent->WritesDone();
    (void)agent->Finish();
  }
  // Kept through a restart.
  StopServer();
  StartServer();
  const v1::ListStopsResponse kept = list();
  ASSERT_EQ(kept.stops_size(), 2);
  EXPECT_EQ(kept.stops(0).zone(), "door");
  EXPECT_EQ(kept.stops(0).reason(), "cleaning");
  EXPECT_EQ(kept.stops(1).zone(), "");
  // Cleared one by one; clearing again is NOT_FOUND.
  grpc::ClientContext resume_context;
  v1::ResumeRobotsRequest resume;
  resume.mutable_scope()->set_whole_fleet(true);
  v1::ResumeRobotsResponse resumed;
  ASSERT_TRUE(fleet_->ResumeRobots(&resume_context, resume, &resumed).ok());
  grpc::ClientContext again_context;
  EXPECT_EQ(fleet_->ResumeRobots(&again_context, resume, &resumed).error_code(),
            grpc::StatusCode::NOT_FOUND);
  ASSERT_EQ(list().stops_size(), 1);
}

TEST_F(ZonesTest, FleetnavctlStopsAndResumesAZoneOrTheFleet) {
  PutHall();
  v1::PutZonesResponse put;
  ASSERT_TRUE(PutZones(ToProto(HallZones()), &put).ok());
  const auto run = [&](std::vector<std::string> args) {
    args.insert(args.begin(), FLEETNAV_FLEETNAVCTL_PATH);
    args.push_back("--server=127.0.0.1:" + std::to_string(port_));
    const std::string base = testing::UniqueTempPath("stops-ctl");
    scenario::ChildProcess child(args, base + ".out", base + ".err");
    EXPECT_TRUE(child.started());
    const int code = child.Wait(30.0).value_or(-1);
    return std::tuple<int, std::string, std::string>{code, child.Stdout(), child.Stderr()};
  };
  EXPECT_EQ(std::get<0>(run({"stop"})), 2);  // neither --all nor --zone
  EXPECT_EQ(std::get<0>(run({"stop", "--all", "--zone", "pen"})), 2);
  EXPECT_EQ(std::get<0>(run({"stop", "--zone", "kitchen"})), 3);
  auto [code, out, err] = run({"stop", "--zone", "pen", "--reason", "spill", "--json"});
  ASSERT_EQ(code, 0) << err;
  EXPECT_EQ(nlohmann::json::parse(out)["map_id"], "hall");
  EXPECT_EQ(nlohmann::json::parse(out)["reason"], "spill");
  auto [all_code, all_out, all_err] = run({"stop", "--all"});
  ASSERT_EQ(all_code, 0) << all_err;
  EXPECT_THAT(all_out, HasSubstr("stopped the whole fleet"));
  auto [list_code, list_out, list_err] = run({"stops", "--json"});
  ASSERT_EQ(list_code, 0) << list_err;
  const nlohmann::json stops = nlohmann::json::parse(list_out);
  ASSERT_EQ(stops.size(), 2u);
  EXPECT_EQ(stops[0]["zone"], "pen");
  EXPECT_EQ(stops[1]["whole_fleet"], true);
  auto [resume_code, resume_out, resume_err] = run({"resume", "--zone", "pen", "--json"});
  ASSERT_EQ(resume_code, 0) << resume_err;
  EXPECT_EQ(nlohmann::json::parse(resume_out)["resumed"]["zone"], "pen");
  EXPECT_EQ(std::get<0>(run({"resume", "--zone", "pen"})), 3);
  EXPECT_EQ(std::get<0>(run({"resume", "--all"})), 0);
}

}  // namespace
}  // namespace fleetnav
