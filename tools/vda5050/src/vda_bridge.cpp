#include "fleetnav/vda5050/vda_bridge.hpp"

#include <grpcpp/client_context.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/time/time.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/proto/geometry_convert.hpp"
#include "fleetnav/proto/grpc_status.hpp"
#include "fleetnav/vda5050/vda_json.hpp"
#include "fleetnav/vda5050/vda_topics.hpp"

namespace fleetnav::vda5050 {
namespace {

/// QoS of what the bridge sends. The specification recommends 0 for orders (§6.2); 1 keeps an
/// order from being dropped between broker and vehicle, and a vehicle ignores the same order
/// and update received twice (§6.6.4.3).
constexpr int kCommandQos = 1;

std::optional<Kinematics> KinematicsOf(const std::string& agv_kinematic) {
  if (agv_kinematic == "DIFF") return Kinematics::kDifferential;
  if (agv_kinematic == "OMNI") return Kinematics::kOmnidirectional;
  if (agv_kinematic == "THREEWHEEL") return Kinematics::kAckermann;
  return std::nullopt;
}

/// Length (x) and width (y) of the model's footprint.
std::pair<double, double> FootprintSize(const RobotModel& model) {
  double min_x = 0, max_x = 0, min_y = 0, max_y = 0;
  for (const Eigen::Vector2d& p : model.footprint_m) {
    min_x = std::min(min_x, p.x());
    max_x = std::max(max_x, p.x());
    min_y = std::min(min_y, p.y());
    max_y = std::max(max_y, p.y());
  }
  return {max_x - min_x, max_y - min_y};
}

/// The planned poses thinned to nodes at most `spacing_m` apart, and where the heading turns by
/// more than 30°; the last pose always.
std::vector<Pose2> Thin(const std::vector<Pose2>& path, double spacing_m) {
  std::vector<Pose2> nodes;
  if (path.empty()) return nodes;
  Pose2 last = path.front();
  for (size_t i = 1; i + 1 < path.size(); ++i) {
    const double along = (path[i].translation() - last.translation()).norm();
    const double turned = std::abs(NormalizeAngle(path[i].yaw_rad() - last.yaw_rad()));
    if (along >= spacing_m || (along > 0.3 && turned > 0.52)) {
      nodes.push_back(path[i]);
      last = path[i];
    }
  }
  nodes.push_back(path.back());
  return nodes;
}

/// Parses `payload` with `parse` into `*out`: the message's header, or why it was refused.
template <typename Message>
absl::StatusOr<const Header*> ParseInto(absl::StatusOr<Message> (*parse)(std::string_view),
                                        const std::string& payload, std::optional<Message>* out) {
  absl::StatusOr<Message> message = parse(payload);
  if (!message.ok()) return message.status();
  return &out->emplace(*std::move(message)).header;
}

}  // namespace

VdaBridge::VdaBridge(BridgeParams params, std::shared_ptr<grpc::Channel> fleetnavd,
                     const Clock* clock, std::function<void(const std::string&)> log)
    : params_(std::move(params)),
      channel_(std::move(fleetnavd)),
      fleet_(v1::FleetService::NewStub(channel_)),
      clock_(clock),
      log_(std::move(log)) {}

VdaBridge::~VdaBridge() { Stop(); }

absl::Status VdaBridge::Start(MqttClient* mqtt) {
  ASSIGN_OR_RETURN(model_, RobotModelByKind(params_.kind));
  mqtt_ = mqtt;
  for (const char* topic : {"connection", "factsheet", "state", "visualization"}) {
    RETURN_IF_ERROR(mqtt_->Subscribe(absl::StrCat(params_.interface_name, "/v2/+/+/", topic), 1));
  }
  pump_ = std::thread([this] {
    while (!stop_.WaitForNotificationWithTimeout(absl::Seconds(params_.pump_period_s))) {
      PumpOnce();
    }
  });
  return absl::OkStatus();
}

void VdaBridge::Stop() {
  if (!stop_.HasBeenNotified()) stop_.Notify();
  if (pump_.joinable()) pump_.join();
  absl::MutexLock lock(&mutex_);
  for (auto& [key, vehicle] : vehicles_) {
    if (vehicle->link != nullptr) vehicle->link->Close(1.0);
  }
}

BridgeCounters VdaBridge::counters() const {
  absl::MutexLock lock(&mutex_);
  BridgeCounters counters = counters_;
  counters.vehicles = 0;
  for (const auto& [key, vehicle] : vehicles_) counters.vehicles += vehicle->link != nullptr;
  return counters;
}

VdaBridge::Vehicle& VdaBridge::VehicleFor(const std::string& manufacturer,
                                          const std::string& serial) {
  std::unique_ptr<Vehicle>& vehicle = vehicles_[absl::StrCat(manufacturer, "/", serial)];
  if (vehicle == nullptr) {
    vehicle = std::make_unique<Vehicle>(Vehicle{manufacturer, serial, std::nullopt, false, false,
                                                VehicleSession(RobotIdFor(manufacturer, serial))});
  }
  return *vehicle;
}

void VdaBridge::OnMessage(const std::string& topic, const std::string& payload) {
  const std::optional<VehicleTopic> where = ParseTopic(topic);
  if (!where || where->interface_name != params_.interface_name) return;
  const std::string name = absl::StrCat(where->manufacturer, "/", where->serial_number);
  // Parsed before the lock: the checks are the costly part.
  std::optional<Connection> connection;
  std::optional<Factsheet> factsheet;
  std::optional<State> state;
  std::optional<Visualization> visualization;
  absl::StatusOr<const Header*> header;
  if (where->topic == "connection") {
    header = ParseInto(&ParseConnection, payload, &connection);
  } else if (where->topic == "factsheet") {
    header = ParseInto(&ParseFactsheet, payload, &factsheet);
  } else if (where->topic == "state") {
    header = ParseInto(&ParseState, payload, &state);
  } else if (where->topic == "visualization") {
    header = ParseInto(&ParseVisualization, payload, &visualization);
  } else {
    return;
  }
  absl::Status parsed = header.status();
  if (parsed.ok() && ((*header)->manufacturer != where->manufacturer ||
                      (*header)->serial_number != where->serial_number)) {
    parsed = absl::InvalidArgumentError(
        absl::StrCat(where->topic, ": the header names ", (*header)->manufacturer, "/",
                     (*header)->serial_number, ", the topic ", name, " (§6.3, §6.4)"));
  }
  absl::MutexLock lock(&mutex_);
  if (!parsed.ok()) {
    ++counters_.refused_malformed;
    Log(absl::StrCat("vda5050: ", name, ": refused ", where->topic, ": ", parsed.message()));
    return;
  }
  const bool known = vehicles_.contains(name);
  if (!known && (state || visualization)) {
    if (counters_.refused_unknown++ % 100 == 0) {
      Log(absl::StrCat("vda5050: ", where->topic, " from ", name,
                       ", which never said it is online: left out"));
    }
    return;
  }
  Vehicle& vehicle = VehicleFor(where->manufacturer, where->serial_number);
  // `connection` is not checked for order: a last will carries the header of the connect
  // (§6.14), and a vehicle that restarted counts from 0 again — its ONLINE starts a new count
  // for every topic.
  if (connection && connection->state == ConnectionState::kOnline) vehicle.session.ResetHeaders();
  if (!connection && !vehicle.session.Fresh(where->topic, (*header)->header_id)) {
    ++counters_.refused_stale;
    Log(absl::StrCat("vda5050: ", name, ": ", where->topic, " headerId ", (*header)->header_id,
                     " is not above the last one: left out (§6.4)"));
    return;
  }
  if (connection) {
    const bool online = connection->state == ConnectionState::kOnline;
    if (online != vehicle.online) {
      Log(absl::StrCat("vda5050: ", name, " is ",
                       std::string(ConnectionStateName(connection->state))));
    }
    vehicle.online = online;
    if (!online) {
      vehicle.link.reset();  // fleetnavd sees the robot go offline
      return;
    }
    if (!vehicle.factsheet) {
      Action request;
      request.action_type = "factsheetRequest";
      request.action_id = absl::StrCat("factsheet-", vehicle.next_action_id++);
      request.blocking_type = BlockingType::kNone;
      PublishInstant(vehicle, request);
    }
    MaybeRegister(vehicle);
    // A vehicle back online may have lost its order (it restarted): send it again; one that
    // kept it ignores the copy (§6.6.4.3).
    if (const JobOrder* order = vehicle.session.order(); order != nullptr) {
      PublishOrder(vehicle, order->last());
    }
  } else if (factsheet) {
    vehicle.factsheet = *factsheet;
    vehicle.refused = false;  // judged again on the new factsheet
    MaybeRegister(vehicle);
  } else if (state) {
    if (!vehicle.online) {
      ++counters_.refused_unknown;
      return;
    }
    const std::string job_before = vehicle.session.job_id();
    VehicleSession::Outcome outcome = vehicle.session.OnState(*state, clock_->NowNs());
    MaybeRegister(vehicle);  // once its position is known
    if (vehicle.link == nullptr) return;
    for (const JobEvent& event : outcome.events) vehicle.link->ReportEvent(event);
    vehicle.link->Publish(outcome.telemetry);
    if (!job_before.empty() && vehicle.session.job_id().empty()) {
      vehicle.link->SetCurrentJob("");
    }
    ++counters_.states;
  } else if (visualization && vehicle.link != nullptr) {
    vehicle.link->Publish(vehicle.session.OnVisualization(*visualization, clock_->NowNs()));
  }
}

void VdaBridge::MaybeRegister(Vehicle& vehicle) {
  // Registered once it is online, its factsheet is known and a state told where it is (so
  // that fleetnavd dispatches to a robot with a pose).
  if (!vehicle.online || !vehicle.factsheet || !vehicle.session.pose() || vehicle.link != nullptr ||
      vehicle.refused) {
    return;
  }
  const std::string name = absl::StrCat(vehicle.manufacturer, "/", vehicle.serial);
  const Factsheet& factsheet = *vehicle.factsheet;
  const std::optional<Kinematics> kinematics = KinematicsOf(factsheet.agv_kinematic);
  if (kinematics != model_.kinematics) {
    Log(absl::StrCat("vda5050: ", name, " (", factsheet.agv_kinematic,
                     ") is not registered: --kind ", params_.kind, " is ",
                     std::string(KinematicsName(model_.kinematics))));
    vehicle.refused = true;
    return;
  }
  const auto [length_m, width_m] = FootprintSize(model_);
  if (factsheet.length_m > length_m + 0.01 || factsheet.width_m > width_m + 0.01) {
    Log(absl::StrCat("vda5050: ", name, " (", factsheet.length_m, " x ", factsheet.width_m,
                     " m) is not registered: larger than --kind ", params_.kind, " (", length_m,
                     " x ", width_m, " m), whose footprint traffic coordination would use"));
    vehicle.refused = true;
    return;
  }
  RobotIdentity identity{vehicle.session.robot_id(),
                         model_,
                         {"free_navigation"},
                         absl::StrCat("vda5050 ", factsheet.series_name)};
  identity.model.limits.max_speed_mps =
      std::min(identity.model.limits.max_speed_mps, factsheet.speed_max_mps);
  vehicle.link = std::make_unique<agent::ServerLink>(channel_, identity);
  if (!vehicle.session.job_id().empty()) vehicle.link->SetCurrentJob(vehicle.session.job_id());
  Log(absl::StrCat("vda5050: ", name, " registered as robot ", identity.robot_id, " (",
                   params_.kind, ")"));
}

void VdaBridge::Publish(Vehicle& vehicle, const std::string& topic, const std::string& payload) {
  const absl::Status sent =
      mqtt_->Publish(TopicFor(params_.interface_name, vehicle.manufacturer, vehicle.serial, topic),
                     payload, kCommandQos, /*retain=*/false);
  if (!sent.ok()) Log(absl::StrCat("vda5050: ", sent.message()));
}

Header VdaBridge::NextHeader(const Vehicle& vehicle, uint32_t* counter) const {
  Header header;
  header.header_id = (*counter)++;
  header.timestamp = Timestamp(clock_->UnixMs());
  header.manufacturer = vehicle.manufacturer;
  header.serial_number = vehicle.serial;
  return header;
}

void VdaBridge::PublishOrder(Vehicle& vehicle, Order order) {
  order.header = NextHeader(vehicle, &vehicle.order_header_id);
  Publish(vehicle, "order", ToJson(order));
  ++counters_.orders;
}

void VdaBridge::PublishInstant(Vehicle& vehicle, Action action) {
  InstantActions message;
  message.header = NextHeader(vehicle, &vehicle.instant_header_id);
  message.actions.push_back(std::move(action));
  Publish(vehicle, "instantActions", ToJson(message));
  ++counters_.instant_actions;
}

absl::StatusOr<std::vector<OrderWaypoint>> VdaBridge::PlanWaypoints(const JobAssignment& assignment,
                                                                    const Pose2& start,
                                                                    const std::string& robot_id) {
  std::vector<OrderWaypoint> waypoints{
      {start.x_m(), start.y_m(), std::nullopt, std::max(assignment.resume.action_index, 0), false}};
  Pose2 from = start;
  const std::vector<RouteAction>& actions = assignment.route->actions;
  for (int i = std::max(assignment.resume.action_index, 0); i < static_cast<int>(actions.size());
       ++i) {
    const auto* free = std::get_if<FreeNavigationAction>(&actions[i].params);
    if (free == nullptr) {
      return absl::FailedPreconditionError(absl::StrCat(
          "action ", i, " is ", std::string(ActionTypeName(actions[i].params)),
          ": a VDA 5050 vehicle runs free-navigation actions only (nodes on the map)"));
    }
    std::vector<Pose2> targets;
    for (size_t w = 0; w < free->waypoints_m.size(); ++w) {
      const Eigen::Vector2d next =
          w + 1 < free->waypoints_m.size() ? free->waypoints_m[w + 1] : free->goal.translation();
      const Eigen::Vector2d heading = next - free->waypoints_m[w];
      targets.emplace_back(free->waypoints_m[w].x(), free->waypoints_m[w].y(),
                           std::atan2(heading.y(), heading.x()));
    }
    targets.push_back(free->goal);
    for (size_t t = 0; t < targets.size(); ++t) {
      v1::PlanPathsRequest request;
      request.set_map_id(assignment.job.map_id);
      request.set_map_version(assignment.map_version);
      request.set_time_limit_s(2.0);
      v1::PlanPathsRequest::Agent* agent = request.add_agents();
      agent->set_robot_id(robot_id);
      agent->set_kind_name(params_.kind);
      *agent->mutable_start() = ToProto(from);
      *agent->mutable_goal() = ToProto(targets[t]);
      grpc::ClientContext context;
      context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(10));
      v1::PlanPathsResponse response;
      const grpc::Status status = fleet_->PlanPaths(&context, request, &response);
      if (!status.ok()) {
        return absl::Status(static_cast<absl::StatusCode>(status.error_code()),
                            absl::StrCat("planning action ", i, ": ", status.error_message()));
      }
      std::vector<Pose2> path;
      if (response.paths_size() == 1) {
        for (const v1::TimedPose& timed : response.paths(0).poses()) {
          absl::StatusOr<Pose2> pose = FromProto(timed.pose());
          if (pose.ok()) path.push_back(*pose);
        }
      }
      if (path.empty()) path = {from, targets[t]};
      path.back() = targets[t];  // the action's own target, not the planning cell's centre
      const std::vector<Pose2> nodes = Thin(path, params_.node_spacing_m);
      for (size_t n = 0; n < nodes.size(); ++n) {
        const bool end = t + 1 == targets.size() && n + 1 == nodes.size();
        waypoints.push_back({nodes[n].x_m(), nodes[n].y_m(),
                             end ? std::optional<double>(nodes[n].yaw_rad()) : std::nullopt, i,
                             end});
      }
      from = targets[t];
    }
  }
  return waypoints;
}

void VdaBridge::PumpOnce() {
  struct Pending {
    std::string key;
    std::string robot_id;
    JobAssignment assignment;
    std::optional<Pose2> pose;
  };
  std::vector<Pending> pending;
  {
    absl::MutexLock lock(&mutex_);
    for (auto& [key, vehicle] : vehicles_) {
      if (vehicle->link == nullptr) continue;
      for (const JobCommand& command : vehicle->link->TakeCommands()) {
        if (command.type == JobCommandType::kClearance) {
          if (std::optional<Order> update =
                  vehicle->session.Clear(command.job_id, command.cleared_up_to_action)) {
            PublishOrder(*vehicle, *std::move(update));
          }
          continue;
        }
        std::vector<JobEvent> events;
        const bool was_running = !vehicle->session.job_id().empty();
        if (std::optional<Action> action = vehicle->session.Command(
                command, absl::StrCat("fleetnav-", vehicle->next_action_id++), &events)) {
          PublishInstant(*vehicle, *std::move(action));
        }
        for (const JobEvent& event : events) vehicle->link->ReportEvent(event);
        if (was_running && vehicle->session.job_id().empty()) vehicle->link->SetCurrentJob("");
      }
      if (!vehicle->session.job_id().empty()) continue;
      if (std::optional<JobAssignment> assignment = vehicle->link->TakeAssignment()) {
        pending.push_back(
            {key, vehicle->session.robot_id(), *std::move(assignment), vehicle->session.pose()});
      }
    }
  }
  // Planning asks fleetnavd: outside the lock.
  for (Pending& job : pending) {
    absl::StatusOr<std::vector<OrderWaypoint>> waypoints =
        job.pose ? PlanWaypoints(job.assignment, *job.pose, job.robot_id)
                 : absl::FailedPreconditionError("the vehicle has not reported its position");
    absl::StatusOr<JobOrder> order =
        waypoints.ok()
            ? JobOrder::Create(absl::StrCat(job.assignment.job.job_id, "-", clock_->UnixMs()),
                               job.assignment.job.map_id, *std::move(waypoints), params_.order)
            : absl::StatusOr<JobOrder>(waypoints.status());
    absl::MutexLock lock(&mutex_);
    const auto found = vehicles_.find(job.key);
    if (found == vehicles_.end() || found->second->link == nullptr) continue;
    Vehicle& vehicle = *found->second;
    const std::string& job_id = job.assignment.job.job_id;
    vehicle.link->SetCurrentJob(job_id);
    if (!order.ok()) {
      JobEvent failed;
      failed.job_id = job_id;
      failed.type = JobEventType::kFailed;
      failed.robot_id = job.robot_id;
      failed.action_index = std::max(job.assignment.resume.action_index, 0);
      failed.reason = std::string(order.status().message());
      vehicle.link->ReportEvent(failed);
      vehicle.link->SetCurrentJob("");
      Log(absl::StrCat("vda5050: job ", job_id, " for ", job.robot_id,
                       " failed: ", order.status().message()));
      continue;
    }
    PublishOrder(vehicle, vehicle.session.Start(job_id, *std::move(order),
                                                std::max(job.assignment.resume.action_index, 0)));
    Log(absl::StrCat("vda5050: job ", job_id, " sent to ", job.robot_id, " as order ",
                     vehicle.session.order()->order_id(), " (",
                     vehicle.session.order()->node_count(), " nodes)"));
  }
}

}  // namespace fleetnav::vda5050
