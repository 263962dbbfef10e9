#include <google/protobuf/util/json_util.h>
#include <grpcpp/client_context.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/time/clock.h"
#include "absl/time/time.h"
#include "call_internal.hpp"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/core/stripe_marker.hpp"
#include "fleetnav/ctl/commands.hpp"
#include "fleetnav/ctl/progress.hpp"
#include "fleetnav/ctl/table.hpp"
#include "fleetnav/proto/grpc_status.hpp"
#include "fleetnav/proto/map_convert.hpp"
#include "fleetnav/proto/route_convert.hpp"
#include "fleetnav/v1/fleet_service.grpc.pb.h"

namespace fleetnav::ctl {
namespace {

std::string Lower(std::string name, const std::string& prefix) {
  if (name.rfind(prefix, 0) == 0) name = name.substr(prefix.size());
  for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return name;
}

std::string StateName(v1::JobState state) { return Lower(v1::JobState_Name(state), "JOB_STATE_"); }

std::string EventName(v1::JobEventType type) {
  return Lower(v1::JobEventType_Name(type), "JOB_EVENT_TYPE_");
}

/// The message as protobuf's JSON mapping (lowerCamelCase field names), on one line.
absl::Status PrintJson(const CommandContext& context, const google::protobuf::Message& message) {
  std::string text;
  if (!google::protobuf::util::MessageToJsonString(message, &text).ok()) {
    return absl::InternalError("cannot print the answer as JSON");
  }
  *context.out << text << '\n';
  return absl::OkStatus();
}

std::string TimeText(int64_t unix_ms) {
  return absl::FormatTime("%H:%M:%E3S", absl::FromUnixMillis(unix_ms), absl::LocalTimeZone());
}

nlohmann::json JobJson(const v1::Job& job) {
  return {{"job_id", job.job_id()},
          {"state", StateName(job.state())},
          {"route", job.route_name()},
          {"route_version", job.route_version()},
          {"robot", job.assigned_robot_id()},
          {"priority", job.priority()},
          {"progress", job.progress_fraction()},
          {"idempotency_key", job.idempotency_key()},
          {"created_unix_ms", job.created_unix_ms()},
          {"reason", job.reason()}};
}

}  // namespace

absl::Status PutMarkers(const CommandContext& context, const std::string& map_id,
                        const std::string& yaml_path) {
  absl::StatusOr<MarkerSet> markers = LoadMarkerSet(yaml_path);
  if (!markers.ok()) return markers.status();
  if (!map_id.empty()) markers->map_id = map_id;
  auto stub = v1::FleetService::NewStub(context.channel);
  grpc::ClientContext rpc;
  PrepareCall(context, &rpc);
  v1::PutMarkerSetRequest request;
  *request.mutable_marker_set() = ToProto(*markers);
  v1::PutMarkerSetResponse response;
  if (absl::Status s = FromGrpcStatus(stub->PutMarkerSet(&rpc, request, &response)); !s.ok()) {
    return s;
  }
  if (context.json) {
    *context.out << nlohmann::json{{"map_id", response.map_id()},
                                   {"version", response.version()},
                                   {"markers", markers->markers.size()}}
                        .dump()
                 << '\n';
    return absl::OkStatus();
  }
  *context.out << "stored " << markers->markers.size() << " marker(s) of map '" << response.map_id()
               << "' as version " << response.version() << '\n';
  return absl::OkStatus();
}

absl::Status GetMarkers(const CommandContext& context, const std::string& map_id,
                        uint32_t version) {
  auto stub = v1::FleetService::NewStub(context.channel);
  grpc::ClientContext rpc;
  PrepareCall(context, &rpc);
  v1::GetMarkerSetRequest request;
  request.set_map_id(map_id);
  request.set_version(version);
  v1::GetMarkerSetResponse response;
  if (absl::Status s = FromGrpcStatus(stub->GetMarkerSet(&rpc, request, &response)); !s.ok()) {
    return s;
  }
  if (context.json) return PrintJson(context, response);
  absl::StatusOr<MarkerSet> markers = FromProto(response.marker_set());
  if (!markers.ok()) return markers.status();
  *context.out << "# version " << response.version() << '\n' << MarkerSetToYaml(*markers);
  return absl::OkStatus();
}

absl::Status DeleteMarkers(const CommandContext& context, const std::string& map_id) {
  v1::DeleteMarkerSetRequest request;
  request.set_map_id(map_id);
  v1::DeleteMarkerSetResponse response;
  return CallAndSay(
      context,
      [&] {
        return context.json ? nlohmann::json{{"deleted_markers_of", map_id}}.dump()
                            : "deleted the marker set of map '" + map_id + "'";
      },
      [&](auto& stub, auto* rpc) { return stub.DeleteMarkerSet(rpc, request, &response); });
}

absl::Status PutRoute(const CommandContext& context, const std::string& yaml_path) {
  absl::StatusOr<Route> route = LoadRoute(yaml_path);
  if (!route.ok()) return route.status();
  auto stub = v1::FleetService::NewStub(context.channel);
  grpc::ClientContext rpc;
  PrepareCall(context, &rpc);
  v1::PutRouteRequest request;
  *request.mutable_route() = ToProto(*route);
  v1::PutRouteResponse response;
  if (absl::Status s = FromGrpcStatus(stub->PutRoute(&rpc, request, &response)); !s.ok()) return s;
  if (context.json) {
    *context.out << nlohmann::json{{"name", response.name()},
                                   {"version", response.version()},
                                   {"actions", route->actions.size()}}
                        .dump()
                 << '\n';
    return absl::OkStatus();
  }
  *context.out << "stored route '" << response.name() << "' (" << route->actions.size()
               << " actions) as version " << response.version() << '\n';
  return absl::OkStatus();
}

absl::Status GetRoute(const CommandContext& context, const std::string& name) {
  auto stub = v1::FleetService::NewStub(context.channel);
  grpc::ClientContext rpc;
  PrepareCall(context, &rpc);
  v1::GetRouteRequest request;
  request.set_name(name);
  v1::GetRouteResponse response;
  if (absl::Status s = FromGrpcStatus(stub->GetRoute(&rpc, request, &response)); !s.ok()) return s;
  if (context.json) return PrintJson(context, response);
  absl::StatusOr<Route> route = FromProto(response.route());
  if (!route.ok()) return route.status();
  *context.out << "# version " << response.version() << '\n' << RouteToYaml(*route);
  return absl::OkStatus();
}

absl::Status ListRoutes(const CommandContext& context, const std::string& map_id) {
  auto stub = v1::FleetService::NewStub(context.channel);
  grpc::ClientContext rpc;
  PrepareCall(context, &rpc);
  v1::ListRoutesRequest request;
  request.set_map_id(map_id);
  v1::ListRoutesResponse response;
  if (absl::Status s = FromGrpcStatus(stub->ListRoutes(&rpc, request, &response)); !s.ok()) {
    return s;
  }
  if (context.json) {
    nlohmann::json routes = nlohmann::json::array();
    for (const v1::Route& r : response.routes()) {
      routes.push_back({{"name", r.name()}, {"map", r.map_id()}, {"actions", r.actions_size()}});
    }
    *context.out << routes.dump() << '\n';
    return absl::OkStatus();
  }
  Table table({"ROUTE", "MAP", "ACTIONS"});
  for (const v1::Route& r : response.routes()) {
    table.AddRow({r.name(), r.map_id(), absl::StrCat(r.actions_size())});
  }
  table.Print(*context.out);
  return absl::OkStatus();
}

absl::Status DeleteRoute(const CommandContext& context, const std::string& name) {
  v1::DeleteRouteRequest request;
  request.set_name(name);
  v1::DeleteRouteResponse response;
  return CallAndSay(
      context,
      [&] {
        return context.json ? nlohmann::json{{"deleted", name}}.dump()
                            : "deleted route '" + name + "'";
      },
      [&](auto& stub, auto* rpc) { return stub.DeleteRoute(rpc, request, &response); });
}

absl::StatusOr<std::string> SubmitJob(const CommandContext& context, const SubmitOptions& options) {
  auto stub = v1::FleetService::NewStub(context.channel);
  grpc::ClientContext rpc;
  PrepareCall(context, &rpc);
  v1::SubmitJobRequest request;
  if (options.goal.empty()) {
    request.set_route_name(options.route_name);
  } else {
    // A go-to-goal: the server sends it as one free-navigation action (robots that advertise
    // free_navigation run it).
    request.mutable_goal()->set_map_id(options.goal_map_id);
    v1::Pose2* goal = request.mutable_goal()->mutable_goal();
    goal->set_x_m(options.goal[0]);
    goal->set_y_m(options.goal[1]);
    goal->set_yaw_rad(options.goal[2] * kPi / 180.0);
  }
  request.set_robot_id(options.robot_id);
  request.set_priority(options.priority);
  request.set_idempotency_key(options.idempotency_key);
  request.set_on_robot_lost(options.requeue_on_robot_lost ? v1::REQUEUE_POLICY_REQUEUE
                                                          : v1::REQUEUE_POLICY_FAIL);
  v1::SubmitJobResponse response;
  if (absl::Status s = FromGrpcStatus(stub->SubmitJob(&rpc, request, &response)); !s.ok()) {
    return s;
  }
  if (context.json) {
    nlohmann::json out = JobJson(response.job());
    out["deduplicated"] = response.deduplicated();
    *context.out << out.dump() << '\n';
  } else {
    *context.out << (response.deduplicated() ? "already submitted: " : "submitted ")
                 << response.job().job_id() << " (" << StateName(response.job().state()) << ")\n";
  }
  return response.job().job_id();
}

absl::Status GetJob(const CommandContext& context, const std::string& job_id) {
  auto stub = v1::FleetService::NewStub(context.channel);
  grpc::ClientContext rpc;
  PrepareCall(context, &rpc);
  v1::GetJobRequest request;
  request.set_job_id(job_id);
  v1::GetJobResponse response;
  if (absl::Status s = FromGrpcStatus(stub->GetJob(&rpc, request, &response)); !s.ok()) return s;
  *context.out << JobJson(response.job()).dump(context.json ? -1 : 2) << '\n';
  return absl::OkStatus();
}

absl::Status ListJobs(const CommandContext& context, const std::string& state,
                      const std::string& robot_id, uint32_t page_size) {
  v1::ListJobsRequest request;
  if (!state.empty()) {
    v1::JobState parsed;
    std::string upper = "JOB_STATE_";
    for (char c : state) upper += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (!v1::JobState_Parse(upper, &parsed)) {
      return absl::InvalidArgumentError(absl::StrCat("--state: unknown state '", state, "'"));
    }
    request.add_states(parsed);
  }
  request.set_robot_id(robot_id);
  request.set_page_size(page_size);
  auto stub = v1::FleetService::NewStub(context.channel);
  std::vector<v1::Job> jobs;
  do {
    grpc::ClientContext rpc;
    PrepareCall(context, &rpc);
    v1::ListJobsResponse page;
    if (absl::Status s = FromGrpcStatus(stub->ListJobs(&rpc, request, &page)); !s.ok()) return s;
    jobs.insert(jobs.end(), page.jobs().begin(), page.jobs().end());
    request.set_page_token(page.next_page_token());
  } while (!request.page_token().empty());
  if (context.json) {
    nlohmann::json out = nlohmann::json::array();
    for (const v1::Job& job : jobs) out.push_back(JobJson(job));
    *context.out << out.dump() << '\n';
    return absl::OkStatus();
  }
  Table table({"JOB", "STATE", "ROUTE", "ROBOT", "PRIORITY", "PROGRESS", "CREATED", "REASON"});
  for (const v1::Job& job : jobs) {
    table.AddRow({job.job_id(), StateName(job.state()), job.route_name(), job.assigned_robot_id(),
                  absl::StrCat(job.priority()),
                  absl::StrFormat("%.0f%%", 100.0 * job.progress_fraction()),
                  TimeText(job.created_unix_ms()), job.reason()});
  }
  table.Print(*context.out);
  return absl::OkStatus();
}

absl::Status CancelJob(const CommandContext& context, const std::string& job_id,
                       const std::string& reason) {
  v1::CancelJobRequest request;
  request.set_job_id(job_id);
  request.set_reason(reason);
  v1::CancelJobResponse response;
  return CallAndSay(
      context,
      [&] { return context.json ? JobJson(response.job()).dump() : "cancelled " + job_id; },
      [&](auto& stub, auto* rpc) { return stub.CancelJob(rpc, request, &response); });
}

absl::Status PauseJob(const CommandContext& context, const std::string& job_id,
                      const std::string& reason) {
  v1::PauseJobRequest request;
  request.set_job_id(job_id);
  request.set_reason(reason);
  v1::PauseJobResponse response;
  return CallAndSay(
      context, [&] { return context.json ? JobJson(response.job()).dump() : "paused " + job_id; },
      [&](auto& stub, auto* rpc) { return stub.PauseJob(rpc, request, &response); });
}

absl::Status ResumeJob(const CommandContext& context, const std::string& job_id) {
  v1::ResumeJobRequest request;
  request.set_job_id(job_id);
  v1::ResumeJobResponse response;
  return CallAndSay(
      context, [&] { return context.json ? JobJson(response.job()).dump() : "resumed " + job_id; },
      [&](auto& stub, auto* rpc) { return stub.ResumeJob(rpc, request, &response); });
}

absl::Status WatchJob(const CommandContext& context, const std::string& job_id) {
  auto stub = v1::FleetService::NewStub(context.channel);
  grpc::ClientContext rpc;
  AddToken(context, &rpc);
  v1::WatchJobRequest request;
  request.set_job_id(job_id);
  auto reader = stub->WatchJob(&rpc, request);
  v1::JobEvent event;
  v1::JobEvent last;
  int64_t started_unix_ms = 0;  // the job's STARTED event: the pace is measured from it
  while (reader->Read(&event)) {
    last = event;
    if (event.type() == v1::JOB_EVENT_TYPE_STARTED) started_unix_ms = event.unix_ms();
    if (context.json) {
      *context.out << nlohmann::json{{"job_id", event.job_id()},
                                     {"event", EventName(event.type())},
                                     {"state", StateName(event.state())},
                                     {"robot", event.robot_id()},
                                     {"action", event.action_index()},
                                     {"progress", event.progress_fraction()},
                                     {"reason", event.reason()},
                                     {"unix_ms", event.unix_ms()}}
                          .dump()
                   << '\n';
    } else {
      std::string detail = event.robot_id();
      if (event.type() == v1::JOB_EVENT_TYPE_ACTION_STARTED ||
          event.type() == v1::JOB_EVENT_TYPE_ACTION_FINISHED) {
        absl::StrAppend(&detail, " action ", event.action_index());
      }
      if (!event.reason().empty()) absl::StrAppend(&detail, " — ", event.reason());
      std::string bar = ProgressBar(event.progress_fraction());
      if (started_unix_ms > 0 && event.state() == v1::JOB_STATE_RUNNING) {
        const std::string eta =
            EtaText(started_unix_ms, event.unix_ms(), event.progress_fraction());
        if (!eta.empty()) absl::StrAppend(&bar, " ", eta);
      }
      *context.out << absl::StrFormat("%s  %-16s %-10s %s  %s\n", TimeText(event.unix_ms()),
                                      EventName(event.type()), StateName(event.state()), bar,
                                      detail);
    }
    context.out->flush();
  }
  if (absl::Status s = FromGrpcStatus(reader->Finish()); !s.ok()) return s;
  if (last.state() == v1::JOB_STATE_FAILED || last.state() == v1::JOB_STATE_CANCELLED) {
    return absl::AbortedError(
        absl::StrCat("job ", job_id, " ", StateName(last.state()), ": ", last.reason()));
  }
  return absl::OkStatus();
}

}  // namespace fleetnav::ctl
