#include <grpcpp/client_context.h>

#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "call_internal.hpp"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/ctl/commands.hpp"
#include "fleetnav/ctl/table.hpp"
#include "fleetnav/proto/grpc_status.hpp"
#include "fleetnav/v1/fleet_service.grpc.pb.h"

namespace fleetnav::ctl {
namespace {

std::string ConnectionName(v1::ConnectionState state) {
  switch (state) {
    case v1::CONNECTION_STATE_ONLINE:
      return "online";
    case v1::CONNECTION_STATE_STALE:
      return "stale";
    case v1::CONNECTION_STATE_OFFLINE:
      return "offline";
    default:
      return "unknown";
  }
}

std::string ModeName(v1::NavigationMode mode) {
  std::string name = v1::NavigationMode_Name(mode);
  const std::string prefix = "NAVIGATION_MODE_";
  if (name.rfind(prefix, 0) == 0) name = name.substr(prefix.size());
  for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return name;
}

nlohmann::json RobotJson(const v1::RobotState& robot) {
  const v1::Telemetry& t = robot.last_telemetry();
  return {{"robot_id", robot.robot_id()},
          {"kind", robot.kind_name()},
          {"connection", ConnectionName(robot.connection())},
          {"x_m", t.pose_in_map().pose().x_m()},
          {"y_m", t.pose_in_map().pose().y_m()},
          {"yaw_rad", t.pose_in_map().pose().yaw_rad()},
          {"mode", ModeName(t.mode())},
          {"stamp_ns", t.stamp_ns()},
          {"progress", t.job_progress_fraction()},
          {"job_id", robot.current_job_id()},
          {"traffic_wait", robot.traffic_wait()},
          {"traffic_held_s", robot.traffic_held_s()},
          {"carried_load_m",
           t.has_carried_load_size()
               ? nlohmann::json::array({t.carried_load_size().x_m(), t.carried_load_size().y_m()})
               : nlohmann::json(nullptr)}};
}

std::string PoseCell(const v1::RobotState& robot) {
  const v1::Pose2& p = robot.last_telemetry().pose_in_map().pose();
  return absl::StrFormat("(%7.3f, %7.3f, %6.1f°)", p.x_m(), p.y_m(), p.yaw_rad() * 180.0 / kPi);
}

}  // namespace

absl::Status ListRobots(const CommandContext& context) {
  auto stub = v1::FleetService::NewStub(context.channel);
  grpc::ClientContext rpc;
  PrepareCall(context, &rpc);
  v1::ListRobotsResponse response;
  if (absl::Status s = FromGrpcStatus(stub->ListRobots(&rpc, {}, &response)); !s.ok()) return s;
  if (context.json) {
    nlohmann::json robots = nlohmann::json::array();
    for (const v1::RobotState& robot : response.robots()) robots.push_back(RobotJson(robot));
    *context.out << robots.dump() << '\n';
    return absl::OkStatus();
  }
  Table table(
      {"ROBOT", "KIND", "CONNECTION", "POSE IN MAP (x, y, yaw)", "MODE", "SIM TIME", "WAITS FOR"});
  for (const v1::RobotState& robot : response.robots()) {
    table.AddRow({robot.robot_id(), robot.kind_name(), ConnectionName(robot.connection()),
                  PoseCell(robot), ModeName(robot.last_telemetry().mode()),
                  absl::StrFormat("%.2f s", robot.last_telemetry().stamp_ns() * 1e-9),
                  robot.traffic_wait()});
  }
  table.Print(*context.out);
  return absl::OkStatus();
}

absl::Status ForgetRobot(const CommandContext& context, const std::string& robot_id) {
  v1::ForgetRobotRequest request;
  request.set_robot_id(robot_id);
  v1::ForgetRobotResponse response;
  const std::string done = context.json ? nlohmann::json{{"forgotten", robot_id}}.dump()
                                        : "forgot robot '" + robot_id + "'";
  return CallAndSay(
      context, [&] { return done; },
      [&](auto& stub, auto* rpc) { return stub.ForgetRobot(rpc, request, &response); });
}

absl::Status WatchFleet(const CommandContext& context, double rate_hz, int max_updates,
                        double duration_s) {
  auto stub = v1::FleetService::NewStub(context.channel);
  grpc::ClientContext rpc;
  AddToken(context, &rpc);
  if (duration_s > 0) {
    rpc.set_deadline(std::chrono::system_clock::now() +
                     std::chrono::milliseconds(static_cast<int64_t>(duration_s * 1000)));
  }
  v1::WatchFleetRequest request;
  request.set_rate_hz(rate_hz);
  auto reader = stub->WatchFleet(&rpc, request);
  v1::FleetUpdate update;
  int received = 0;
  while (reader->Read(&update)) {
    for (const std::string& removed : update.removed_robot_ids()) {
      if (context.json) {
        *context.out << nlohmann::json{{"robot_id", removed}, {"removed", true}}.dump() << '\n';
      } else {
        *context.out << absl::StrFormat("%-10s removed\n", removed);
      }
    }
    for (const v1::RobotState& robot : update.robots()) {
      if (context.json) {
        *context.out << RobotJson(robot).dump() << '\n';
      } else {
        *context.out << absl::StrFormat("%-10s %-8s %s  %-10s t=%.2f s  progress %3.0f%%\n",
                                        robot.robot_id(), ConnectionName(robot.connection()),
                                        PoseCell(robot), ModeName(robot.last_telemetry().mode()),
                                        robot.last_telemetry().stamp_ns() * 1e-9,
                                        100.0 * robot.last_telemetry().job_progress_fraction());
      }
    }
    context.out->flush();
    if (max_updates > 0 && ++received >= max_updates) {
      rpc.TryCancel();
      break;
    }
  }
  const grpc::Status status = reader->Finish();
  // Ending by our own deadline or count is a normal end of a watch.
  if (status.error_code() == grpc::StatusCode::DEADLINE_EXCEEDED ||
      status.error_code() == grpc::StatusCode::CANCELLED) {
    return absl::OkStatus();
  }
  return FromGrpcStatus(status);
}

}  // namespace fleetnav::ctl
