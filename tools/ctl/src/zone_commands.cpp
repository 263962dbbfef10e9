// fleetnavctl zones put/get/list/delete: a map's no-go, speed-limit and one-at-a-time zones.
#include <grpcpp/client_context.h>

#include <nlohmann/json.hpp>

#include "absl/strings/str_cat.h"
#include "call_internal.hpp"
#include "fleetnav/core/zone.hpp"
#include "fleetnav/ctl/commands.hpp"
#include "fleetnav/ctl/table.hpp"
#include "fleetnav/proto/grpc_status.hpp"
#include "fleetnav/proto/zone_convert.hpp"
#include "fleetnav/v1/fleet_service.grpc.pb.h"

namespace fleetnav::ctl {
namespace {

nlohmann::json ZoneJson(const Zone& zone) {
  nlohmann::json polygon = nlohmann::json::array();
  for (const Eigen::Vector2d& vertex : zone.polygon_in_map) {
    polygon.push_back({vertex.x(), vertex.y()});
  }
  nlohmann::json out = {
      {"name", zone.name}, {"kind", std::string(ZoneKindName(zone.kind))}, {"polygon", polygon}};
  if (zone.kind == ZoneKind::kSpeedLimit) out["speed_limit_mps"] = zone.speed_limit_mps;
  if (zone.kind == ZoneKind::kOneAtATime) out["capacity"] = zone.capacity;
  return out;
}

nlohmann::json StopJson(const v1::RobotStop& stop) {
  return {{"whole_fleet", stop.zone().empty()},
          {"map_id", stop.map_id()},
          {"zone", stop.zone()},
          {"reason", stop.reason()},
          {"created_unix_ms", stop.created_unix_ms()}};
}

std::string StopText(const v1::RobotStop& stop) {
  return stop.zone().empty()
             ? "the whole fleet"
             : absl::StrCat("zone '", stop.zone(), "' of map '", stop.map_id(), "'");
}

v1::StopScope Scope(const StopTarget& target) {
  v1::StopScope scope;
  scope.set_whole_fleet(target.whole_fleet);
  scope.set_map_id(target.map_id);
  scope.set_zone(target.zone);
  return scope;
}

}  // namespace

absl::Status StopRobots(const CommandContext& context, const StopTarget& target,
                        const std::string& reason) {
  v1::StopRobotsRequest request;
  *request.mutable_scope() = Scope(target);
  request.set_reason(reason);
  v1::StopRobotsResponse response;
  return CallAndSay(
      context,
      [&] {
        return context.json ? StopJson(response.stop()).dump()
                            : absl::StrCat("stopped ", StopText(response.stop()),
                                           " (until `fleetnavctl resume`)");
      },
      [&](auto& stub, auto* rpc) { return stub.StopRobots(rpc, request, &response); });
}

absl::Status ResumeRobots(const CommandContext& context, const StopTarget& target) {
  v1::ResumeRobotsRequest request;
  *request.mutable_scope() = Scope(target);
  v1::ResumeRobotsResponse response;
  return CallAndSay(
      context,
      [&] {
        return context.json ? nlohmann::json{{"resumed", StopJson(response.cleared())}}.dump()
                            : absl::StrCat("resumed ", StopText(response.cleared()));
      },
      [&](auto& stub, auto* rpc) { return stub.ResumeRobots(rpc, request, &response); });
}

absl::Status ListStops(const CommandContext& context) {
  auto stub = v1::FleetService::NewStub(context.channel);
  grpc::ClientContext rpc;
  PrepareCall(context, &rpc);
  v1::ListStopsResponse response;
  if (absl::Status s = FromGrpcStatus(stub->ListStops(&rpc, {}, &response)); !s.ok()) return s;
  if (context.json) {
    nlohmann::json stops = nlohmann::json::array();
    for (const v1::RobotStop& stop : response.stops()) stops.push_back(StopJson(stop));
    *context.out << stops.dump() << '\n';
    return absl::OkStatus();
  }
  Table table({"STOPPED", "SINCE_UNIX_MS", "REASON"});
  for (const v1::RobotStop& stop : response.stops()) {
    table.AddRow({StopText(stop), absl::StrCat(stop.created_unix_ms()), stop.reason()});
  }
  table.Print(*context.out);
  return absl::OkStatus();
}

absl::Status PutZones(const CommandContext& context, const std::string& map_id,
                      const std::string& yaml_path) {
  absl::StatusOr<ZoneSet> zones = LoadZoneSet(yaml_path);
  if (!zones.ok()) return zones.status();
  if (!map_id.empty()) zones->map_id = map_id;
  if (zones->map_id.empty()) {
    return absl::InvalidArgumentError(
        absl::StrCat(yaml_path, ": no map: give --map or a `map:` line in the file"));
  }
  v1::PutZonesRequest request;
  *request.mutable_zone_set() = ToProto(*zones);
  v1::PutZonesResponse response;
  return CallAndSay(
      context,
      [&] {
        return context.json ? nlohmann::json{{"map_id", response.map_id()},
                                             {"version", response.version()},
                                             {"zones", zones->zones.size()}}
                                  .dump()
                            : absl::StrCat("stored ", zones->zones.size(), " zone(s) of map '",
                                           response.map_id(), "' as version ", response.version());
      },
      [&](auto& stub, auto* rpc) { return stub.PutZones(rpc, request, &response); });
}

absl::Status GetZones(const CommandContext& context, const std::string& map_id, uint32_t version) {
  v1::GetZonesRequest request;
  request.set_map_id(map_id);
  request.set_version(version);
  v1::GetZonesResponse response;
  auto stub = v1::FleetService::NewStub(context.channel);
  grpc::ClientContext rpc;
  PrepareCall(context, &rpc);
  if (absl::Status s = FromGrpcStatus(stub->GetZones(&rpc, request, &response)); !s.ok()) {
    return s;
  }
  absl::StatusOr<ZoneSet> zones = FromProto(response.zone_set());
  if (!zones.ok()) return zones.status();
  if (context.json) {
    nlohmann::json listed = nlohmann::json::array();
    for (const Zone& zone : zones->zones) listed.push_back(ZoneJson(zone));
    *context.out << nlohmann::json{{"map_id", zones->map_id},
                                   {"version", response.version()},
                                   {"created_unix_ms", response.created_unix_ms()},
                                   {"zones", listed}}
                        .dump()
                 << '\n';
    return absl::OkStatus();
  }
  *context.out << "# version " << response.version() << '\n' << ZoneSetToYaml(*zones);
  return absl::OkStatus();
}

absl::Status ListZones(const CommandContext& context) {
  auto stub = v1::FleetService::NewStub(context.channel);
  grpc::ClientContext rpc;
  PrepareCall(context, &rpc);
  v1::ListZonesResponse response;
  if (absl::Status s = FromGrpcStatus(stub->ListZones(&rpc, {}, &response)); !s.ok()) return s;
  if (context.json) {
    nlohmann::json sets = nlohmann::json::array();
    for (const v1::ZoneSetSummary& set : response.zone_sets()) {
      sets.push_back({{"map_id", set.map_id()},
                      {"version", set.version()},
                      {"created_unix_ms", set.created_unix_ms()},
                      {"no_go", set.no_go_zones()},
                      {"speed_limit", set.speed_limit_zones()},
                      {"one_at_a_time", set.one_at_a_time_zones()}});
    }
    *context.out << sets.dump() << '\n';
    return absl::OkStatus();
  }
  Table table({"MAP", "VERSION", "NO_GO", "SPEED_LIMIT", "ONE_AT_A_TIME"});
  for (const v1::ZoneSetSummary& set : response.zone_sets()) {
    table.AddRow({set.map_id(), absl::StrCat(set.version()), absl::StrCat(set.no_go_zones()),
                  absl::StrCat(set.speed_limit_zones()), absl::StrCat(set.one_at_a_time_zones())});
  }
  table.Print(*context.out);
  return absl::OkStatus();
}

absl::Status DeleteZones(const CommandContext& context, const std::string& map_id) {
  v1::DeleteZonesRequest request;
  request.set_map_id(map_id);
  v1::DeleteZonesResponse response;
  return CallAndSay(
      context,
      [&] {
        return context.json ? nlohmann::json{{"deleted_zones_of", map_id}}.dump()
                            : "deleted the zones of map '" + map_id + "'";
      },
      [&](auto& stub, auto* rpc) { return stub.DeleteZones(rpc, request, &response); });
}

}  // namespace fleetnav::ctl
