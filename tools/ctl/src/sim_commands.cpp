#include "fleetnav/ctl/sim_commands.hpp"

#include <grpcpp/client_context.h>

#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>

#include "absl/status/statusor.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "call_internal.hpp"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/ctl/table.hpp"
#include "fleetnav/proto/grpc_status.hpp"
#include "fleetnav/v1/fleet_service.grpc.pb.h"
#include "fleetnav/v1/sim_service.grpc.pb.h"

namespace fleetnav::ctl {
namespace {

absl::StatusOr<v1::GroundTruth> FetchTruth(const CommandContext& context,
                                           const std::shared_ptr<grpc::Channel>& sim_channel) {
  auto stub = v1::SimService::NewStub(sim_channel);
  grpc::ClientContext rpc;
  PrepareCall(context, &rpc);
  v1::GroundTruth truth;
  absl::Status status = FromGrpcStatus(stub->GetGroundTruth(&rpc, {}, &truth));
  if (!status.ok()) return status;
  return truth;
}

std::string PoseText(const v1::Pose2& p) {
  return absl::StrFormat("(%7.3f, %7.3f, %6.2f°)", p.x_m(), p.y_m(), RadToDeg(p.yaw_rad()));
}

}  // namespace

absl::Status PrintGroundTruth(const CommandContext& context,
                              std::shared_ptr<grpc::Channel> sim_channel) {
  absl::StatusOr<v1::GroundTruth> truth = FetchTruth(context, sim_channel);
  if (!truth.ok()) return truth.status();
  if (context.json) {
    nlohmann::json robots = nlohmann::json::array();
    for (const auto& r : truth->robots()) {
      robots.push_back({{"robot_id", r.robot_id()},
                        {"x_m", r.pose().x_m()},
                        {"y_m", r.pose().y_m()},
                        {"yaw_rad", r.pose().yaw_rad()},
                        {"up_z", r.up_z()},
                        {"collisions", r.collisions()},
                        {"collisions_world", r.collisions_world()},
                        {"collisions_robots", r.collisions_robots()}});
    }
    nlohmann::json trolleys = nlohmann::json::array();
    for (const auto& t : truth->trolleys()) {
      trolleys.push_back({{"trolley_id", t.trolley_id()},
                          {"x_m", t.pose().x_m()},
                          {"y_m", t.pose().y_m()},
                          {"yaw_rad", t.pose().yaw_rad()},
                          {"carrier_robot_id", t.carrier_robot_id()}});
    }
    *context.out << nlohmann::json{{"sim_time_s", truth->sim_time_ns() * 1e-9},
                                   {"robots", robots},
                                   {"trolleys", trolleys},
                                   {"contacts", truth->contacts_size()},
                                   {"min_separation_m", truth->min_separation_m()}}
                 << '\n';
    return absl::OkStatus();
  }
  *context.out << absl::StrFormat("sim time %.2f s, %d contact(s)\n", truth->sim_time_ns() * 1e-9,
                                  truth->contacts_size());
  Table table({"ROBOT", "TRUE POSE (x, y, yaw)", "SPEED", "YAW RATE", "UPRIGHT", "COLLISIONS"});
  for (const auto& r : truth->robots()) {
    table.AddRow({r.robot_id(), PoseText(r.pose()),
                  absl::StrFormat("%.3f m/s", r.velocity().vx_mps()),
                  absl::StrFormat("%.3f rad/s", r.velocity().yaw_rate_radps()),
                  absl::StrFormat("%.3f", r.up_z()),
                  absl::StrFormat("%u (world %u, robots %u)", r.collisions(), r.collisions_world(),
                                  r.collisions_robots())});
  }
  table.Print(*context.out);
  if (truth->trolleys_size() > 0) {
    Table trolleys({"TROLLEY", "TRUE POSE (x, y, yaw)", "CARRIED BY"});
    for (const auto& t : truth->trolleys()) {
      trolleys.AddRow({t.trolley_id(), PoseText(t.pose()),
                       t.carrier_robot_id().empty() ? "-" : t.carrier_robot_id()});
    }
    trolleys.Print(*context.out);
  }
  return absl::OkStatus();
}

absl::Status CompareWithTruth(const CommandContext& context,
                              std::shared_ptr<grpc::Channel> sim_channel,
                              const std::string& robot_id) {
  absl::StatusOr<v1::GroundTruth> truth = FetchTruth(context, sim_channel);
  if (!truth.ok()) return truth.status();
  const v1::RobotGroundTruth* true_robot = nullptr;
  for (const auto& r : truth->robots()) {
    if (r.robot_id() == robot_id) true_robot = &r;
  }
  if (true_robot == nullptr) {
    return absl::NotFoundError(absl::StrCat("robot '", robot_id, "' is not in the simulator"));
  }
  auto stub = v1::FleetService::NewStub(context.channel);
  grpc::ClientContext rpc;
  PrepareCall(context, &rpc);
  v1::GetRobotRequest request;
  request.set_robot_id(robot_id);
  v1::GetRobotResponse response;
  if (absl::Status s = FromGrpcStatus(stub->GetRobot(&rpc, request, &response)); !s.ok()) return s;
  const v1::Pose2& held = response.robot().last_telemetry().pose_in_map().pose();
  const v1::Pose2& real = true_robot->pose();
  const double error_m = std::hypot(held.x_m() - real.x_m(), held.y_m() - real.y_m());
  const double error_deg = std::abs(RadToDeg(AngleDifference(held.yaw_rad(), real.yaw_rad())));
  if (context.json) {
    *context.out << nlohmann::json{{"robot_id", robot_id},
                                   {"server", {held.x_m(), held.y_m(), held.yaw_rad()}},
                                   {"truth", {real.x_m(), real.y_m(), real.yaw_rad()}},
                                   {"position_error_m", error_m},
                                   {"yaw_error_deg", error_deg}}
                 << '\n';
    return absl::OkStatus();
  }
  Table table({"ROBOT", "SOURCE", "POSE (x, y, yaw)"});
  table.AddRow({robot_id, "fleetnavd", PoseText(held)});
  table.AddRow({robot_id, "simulator", PoseText(real)});
  table.Print(*context.out);
  *context.out << absl::StrFormat("difference: %.3f m, %.2f°\n", error_m, error_deg);
  return absl::OkStatus();
}

}  // namespace fleetnav::ctl
