#include "fleetnav/server/rpc/fleet_service.hpp"

#include <chrono>
#include <map>
#include <cmath>
#include <thread>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/map_io.hpp"
#include "fleetnav/proto/map_convert.hpp"
#include "fleetnav/proto/robot_convert.hpp"
#include "fleetnav/proto/telemetry_convert.hpp"
#include "fleetnav/server/rpc/robot_state_convert.hpp"
#include "fleetnav/proto/grpc_status.hpp"

namespace fleetnav::server {
namespace {

void FillInfo(const storage::MapInfo& info, v1::MapInfo* out) {
  out->set_map_id(info.map_id);
  out->set_version(info.version);
  out->set_width(static_cast<uint32_t>(info.width));
  out->set_height(static_cast<uint32_t>(info.height));
  out->set_resolution_m(info.resolution_m);
  out->set_description(info.description);
  out->set_created_unix_ms(info.created_unix_ms);
}

absl::StatusOr<OccupancyGrid> GridFromRequest(const v1::PutMapRequest& request) {
  switch (request.source_case()) {
    case v1::PutMapRequest::kGrid:
      return FromProto(request.grid());
    case v1::PutMapRequest::kMapServer:
      return GridFromMapServerBytes(request.map_server().yaml(), request.map_server().pgm());
    case v1::PutMapRequest::SOURCE_NOT_SET:
      break;
  }
  return absl::InvalidArgumentError("source: send either `grid` or `map_server`");
}

}  // namespace

grpc::Status FleetServiceImpl::PutMap(grpc::ServerContext*, const v1::PutMapRequest* request,
                                      v1::PutMapResponse* response) {
  absl::Status id_status = MapCatalog::ValidateMapId(request->map_id());
  if (!id_status.ok()) return ToGrpcStatus(id_status);
  absl::StatusOr<OccupancyGrid> grid = GridFromRequest(*request);
  if (!grid.ok()) return ToGrpcStatus(grid.status());
  absl::StatusOr<storage::MapInfo> info =
      maps_->Put(request->map_id(), *grid, request->description());
  if (!info.ok()) return ToGrpcStatus(info.status());
  response->set_map_id(info->map_id);
  response->set_version(info->version);
  return grpc::Status::OK;
}

grpc::Status FleetServiceImpl::GetMap(grpc::ServerContext*, const v1::GetMapRequest* request,
                                      v1::GetMapResponse* response) {
  absl::StatusOr<storage::StoredMap> stored = maps_->Get(request->map_id(), request->version());
  if (!stored.ok()) return ToGrpcStatus(stored.status());
  FillInfo(stored->info, response->mutable_info());
  *response->mutable_grid() = fleetnav::ToProto(stored->grid);
  return grpc::Status::OK;
}

grpc::Status FleetServiceImpl::ListMaps(grpc::ServerContext*, const v1::ListMapsRequest*,
                                        v1::ListMapsResponse* response) {
  absl::StatusOr<std::vector<storage::MapInfo>> maps = maps_->List();
  if (!maps.ok()) return ToGrpcStatus(maps.status());
  for (const storage::MapInfo& info : *maps) FillInfo(info, response->add_maps());
  return grpc::Status::OK;
}

grpc::Status FleetServiceImpl::DeleteMap(grpc::ServerContext*, const v1::DeleteMapRequest* request,
                                         v1::DeleteMapResponse*) {
  return ToGrpcStatus(maps_->Delete(request->map_id()));
}

grpc::Status FleetServiceImpl::ListRobots(grpc::ServerContext*, const v1::ListRobotsRequest*,
                                          v1::ListRobotsResponse* response) {
  for (const RobotRecord& record : registry_->Snapshot()) *response->add_robots() = ToProto(record);
  return grpc::Status::OK;
}

grpc::Status FleetServiceImpl::GetRobot(grpc::ServerContext*, const v1::GetRobotRequest* request,
                                        v1::GetRobotResponse* response) {
  absl::StatusOr<RobotRecord> record = registry_->Get(request->robot_id());
  if (!record.ok()) return ToGrpcStatus(record.status());
  *response->mutable_robot() = ToProto(*record);
  return grpc::Status::OK;
}

grpc::Status FleetServiceImpl::WatchFleet(grpc::ServerContext* context,
                                          const v1::WatchFleetRequest* request,
                                          grpc::ServerWriter<v1::FleetUpdate>* writer) {
  const double rate_hz = request->rate_hz() == 0.0 ? 10.0 : request->rate_hz();
  if (!std::isfinite(rate_hz) || rate_hz < 0.0 || rate_hz > 100.0) {
    return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                        absl::StrCat("rate_hz: must be in (0, 100], got ", request->rate_hz()));
  }
  const auto period = std::chrono::duration<double>(1.0 / rate_hz);
  // What this watcher last saw of each robot: its revision and connection state. A robot that
  // goes stale changes no revision, so the state is compared too.
  std::map<std::string, std::pair<uint64_t, ConnectionState>> seen;
  bool first = true;
  while (!context->IsCancelled() && !stopping_->load()) {
    v1::FleetUpdate update;
    update.set_snapshot(first);
    for (const RobotRecord& record : registry_->Snapshot()) {
      auto [it, inserted] = seen.try_emplace(record.identity.robot_id, record.revision,
                                             record.connection);
      const bool changed = inserted || it->second.first != record.revision ||
                           it->second.second != record.connection;
      it->second = {record.revision, record.connection};
      if (first || changed) *update.add_robots() = ToProto(record);
    }
    if (first || update.robots_size() > 0) {
      update.set_server_time_ns(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                    std::chrono::steady_clock::now().time_since_epoch())
                                    .count());
      if (!writer->Write(update)) break;
      first = false;
    }
    std::this_thread::sleep_for(period);
  }
  return grpc::Status::OK;
}

}  // namespace fleetnav::server
