#include "fleetnav/server/rpc/fleet_service.hpp"

#include <chrono>
#include <cmath>
#include <map>
#include <thread>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/map_io.hpp"
#include "fleetnav/proto/geometry_convert.hpp"
#include "fleetnav/proto/grpc_status.hpp"
#include "fleetnav/proto/job_convert.hpp"
#include "fleetnav/proto/map_convert.hpp"
#include "fleetnav/proto/robot_convert.hpp"
#include "fleetnav/proto/route_convert.hpp"
#include "fleetnav/proto/telemetry_convert.hpp"
#include "fleetnav/proto/traffic_plan_convert.hpp"
#include "fleetnav/proto/zone_convert.hpp"

namespace fleetnav::server {
namespace {

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
  absl::StatusOr<MapInfo> info = maps_->Put(request->map_id(), *grid, request->description());
  if (!info.ok()) return ToGrpcStatus(info.status());
  response->set_map_id(info->map_id);
  response->set_version(info->version);
  return grpc::Status::OK;
}

grpc::Status FleetServiceImpl::GetMap(grpc::ServerContext*, const v1::GetMapRequest* request,
                                      v1::GetMapResponse* response) {
  absl::StatusOr<std::shared_ptr<const storage::StoredMap>> stored =
      maps_->Get(request->map_id(), request->version());
  if (!stored.ok()) return ToGrpcStatus(stored.status());
  *response->mutable_info() = ToProto((*stored)->info);
  *response->mutable_grid() = fleetnav::ToProto((*stored)->grid);
  return grpc::Status::OK;
}

grpc::Status FleetServiceImpl::ListMaps(grpc::ServerContext*, const v1::ListMapsRequest*,
                                        v1::ListMapsResponse* response) {
  absl::StatusOr<std::vector<MapInfo>> maps = maps_->List();
  if (!maps.ok()) return ToGrpcStatus(maps.status());
  for (const MapInfo& info : *maps) *response->add_maps() = ToProto(info);
  return grpc::Status::OK;
}

grpc::Status FleetServiceImpl::DeleteMarkerSet(grpc::ServerContext*,
                                               const v1::DeleteMarkerSetRequest* request,
                                               v1::DeleteMarkerSetResponse*) {
  return ToGrpcStatus(site_->DeleteMarkerSet(request->map_id()));
}

grpc::Status FleetServiceImpl::DeleteRoute(grpc::ServerContext*,
                                           const v1::DeleteRouteRequest* request,
                                           v1::DeleteRouteResponse*) {
  return ToGrpcStatus(site_->DeleteRoute(request->name()));
}

grpc::Status FleetServiceImpl::DeleteMap(grpc::ServerContext*, const v1::DeleteMapRequest* request,
                                         v1::DeleteMapResponse*) {
  return ToGrpcStatus(site_->DeleteMap(request->map_id()));
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

grpc::Status FleetServiceImpl::ForgetRobot(grpc::ServerContext*,
                                           const v1::ForgetRobotRequest* request,
                                           v1::ForgetRobotResponse*) {
  return ToGrpcStatus(jobs_->ForgetRobot(request->robot_id()));
}

grpc::Status FleetServiceImpl::PutMarkerSet(grpc::ServerContext*,
                                            const v1::PutMarkerSetRequest* request,
                                            v1::PutMarkerSetResponse* response) {
  absl::StatusOr<MarkerSet> markers = FromProto(request->marker_set());
  if (!markers.ok()) return ToGrpcStatus(markers.status());
  absl::StatusOr<uint32_t> version = site_->PutMarkerSet(*markers);
  if (!version.ok()) return ToGrpcStatus(version.status());
  response->set_map_id(markers->map_id);
  response->set_version(*version);
  return grpc::Status::OK;
}

grpc::Status FleetServiceImpl::GetMarkerSet(grpc::ServerContext*,
                                            const v1::GetMarkerSetRequest* request,
                                            v1::GetMarkerSetResponse* response) {
  absl::StatusOr<std::shared_ptr<const storage::StoredMarkerSet>> stored =
      site_->GetMarkerSet(request->map_id(), request->version());
  if (!stored.ok()) return ToGrpcStatus(stored.status());
  *response->mutable_marker_set() = fleetnav::ToProto((*stored)->markers);
  response->set_version((*stored)->version);
  return grpc::Status::OK;
}

grpc::Status FleetServiceImpl::PutZones(grpc::ServerContext*, const v1::PutZonesRequest* request,
                                        v1::PutZonesResponse* response) {
  absl::StatusOr<ZoneSet> zones = FromProto(request->zone_set());
  if (!zones.ok()) return ToGrpcStatus(zones.status());
  absl::StatusOr<uint32_t> version = zones_->PutZones(*zones);
  if (!version.ok()) return ToGrpcStatus(version.status());
  response->set_map_id(zones->map_id);
  response->set_version(*version);
  return grpc::Status::OK;
}

grpc::Status FleetServiceImpl::GetZones(grpc::ServerContext*, const v1::GetZonesRequest* request,
                                        v1::GetZonesResponse* response) {
  absl::StatusOr<storage::StoredZoneSet> stored =
      zones_->GetZones(request->map_id(), request->version());
  if (!stored.ok()) return ToGrpcStatus(stored.status());
  *response->mutable_zone_set() = fleetnav::ToProto(stored->zones);
  response->set_version(stored->version);
  response->set_created_unix_ms(stored->created_unix_ms);
  return grpc::Status::OK;
}

grpc::Status FleetServiceImpl::ListZones(grpc::ServerContext*, const v1::ListZonesRequest*,
                                         v1::ListZonesResponse* response) {
  absl::StatusOr<std::vector<storage::StoredZoneSet>> listed = zones_->ListZones();
  if (!listed.ok()) return ToGrpcStatus(listed.status());
  for (const storage::StoredZoneSet& stored : *listed)
    *response->add_zone_sets() =
        ToSummaryProto(stored.zones, stored.version, stored.created_unix_ms);
  return grpc::Status::OK;
}

grpc::Status FleetServiceImpl::DeleteZones(grpc::ServerContext*,
                                           const v1::DeleteZonesRequest* request,
                                           v1::DeleteZonesResponse*) {
  return ToGrpcStatus(zones_->DeleteZones(request->map_id()));
}

namespace {

// A scope's zone and map; a whole-fleet scope that also names a zone or map is refused.
absl::Status CheckScope(const v1::StopScope& scope) {
  if (scope.whole_fleet() && (!scope.zone().empty() || !scope.map_id().empty())) {
    return absl::InvalidArgumentError("scope: whole_fleet or a zone, not both");
  }
  if (!scope.whole_fleet() && scope.zone().empty()) {
    return absl::InvalidArgumentError("scope: give whole_fleet or a zone");
  }
  return absl::OkStatus();
}

}  // namespace

grpc::Status FleetServiceImpl::StopRobots(grpc::ServerContext*,
                                          const v1::StopRobotsRequest* request,
                                          v1::StopRobotsResponse* response) {
  if (absl::Status s = CheckScope(request->scope()); !s.ok()) return ToGrpcStatus(s);
  absl::StatusOr<RobotStop> stop =
      stops_->Stop(request->scope().map_id(), request->scope().zone(), request->reason());
  if (!stop.ok()) return ToGrpcStatus(stop.status());
  *response->mutable_stop() = ToProto(*stop);
  return grpc::Status::OK;
}

grpc::Status FleetServiceImpl::ResumeRobots(grpc::ServerContext*,
                                            const v1::ResumeRobotsRequest* request,
                                            v1::ResumeRobotsResponse* response) {
  if (absl::Status s = CheckScope(request->scope()); !s.ok()) return ToGrpcStatus(s);
  absl::StatusOr<RobotStop> cleared =
      stops_->Resume(request->scope().map_id(), request->scope().zone());
  if (!cleared.ok()) return ToGrpcStatus(cleared.status());
  *response->mutable_cleared() = ToProto(*cleared);
  return grpc::Status::OK;
}

grpc::Status FleetServiceImpl::ListStops(grpc::ServerContext*, const v1::ListStopsRequest*,
                                         v1::ListStopsResponse* response) {
  absl::StatusOr<std::vector<RobotStop>> stops = stops_->InForce();
  if (!stops.ok()) return ToGrpcStatus(stops.status());
  for (const RobotStop& stop : *stops) *response->add_stops() = ToProto(stop);
  return grpc::Status::OK;
}

grpc::Status FleetServiceImpl::PutRoute(grpc::ServerContext*, const v1::PutRouteRequest* request,
                                        v1::PutRouteResponse* response) {
  absl::StatusOr<Route> route = FromProto(request->route());
  if (!route.ok()) return ToGrpcStatus(route.status());
  absl::StatusOr<uint32_t> version = site_->PutRoute(*route);
  if (!version.ok()) return ToGrpcStatus(version.status());
  response->set_name(route->name);
  response->set_version(*version);
  return grpc::Status::OK;
}

grpc::Status FleetServiceImpl::GetRoute(grpc::ServerContext*, const v1::GetRouteRequest* request,
                                        v1::GetRouteResponse* response) {
  absl::StatusOr<std::shared_ptr<const storage::StoredRoute>> stored =
      site_->GetRoute(request->name(), 0);
  if (!stored.ok()) return ToGrpcStatus(stored.status());
  *response->mutable_route() = fleetnav::ToProto((*stored)->route);
  response->set_version((*stored)->version);
  return grpc::Status::OK;
}

grpc::Status FleetServiceImpl::ListRoutes(grpc::ServerContext*,
                                          const v1::ListRoutesRequest* request,
                                          v1::ListRoutesResponse* response) {
  absl::StatusOr<std::vector<storage::StoredRoute>> routes = site_->ListRoutes(request->map_id());
  if (!routes.ok()) return ToGrpcStatus(routes.status());
  for (const storage::StoredRoute& stored : *routes) {
    *response->add_routes() = fleetnav::ToProto(stored.route);
  }
  return grpc::Status::OK;
}

grpc::Status FleetServiceImpl::SubmitJob(grpc::ServerContext*, const v1::SubmitJobRequest* request,
                                         v1::SubmitJobResponse* response) {
  absl::StatusOr<SubmitJobRequest> submit = FromProto(*request);
  if (!submit.ok()) return ToGrpcStatus(submit.status());
  absl::StatusOr<storage::CreatedJob> created = jobs_->Submit(*submit);
  if (!created.ok()) return ToGrpcStatus(created.status());
  *response->mutable_job() = fleetnav::ToProto(created->job);
  response->set_deduplicated(created->deduplicated);
  return grpc::Status::OK;
}

grpc::Status FleetServiceImpl::GetJob(grpc::ServerContext*, const v1::GetJobRequest* request,
                                      v1::GetJobResponse* response) {
  absl::StatusOr<Job> job = jobs_->Get(request->job_id());
  if (!job.ok()) return ToGrpcStatus(job.status());
  *response->mutable_job() = fleetnav::ToProto(*job);
  return grpc::Status::OK;
}

grpc::Status FleetServiceImpl::ListJobs(grpc::ServerContext*, const v1::ListJobsRequest* request,
                                        v1::ListJobsResponse* response) {
  absl::StatusOr<JobFilter> filter = FromProto(*request);
  if (!filter.ok()) return ToGrpcStatus(filter.status());
  absl::StatusOr<storage::JobPage> page = jobs_->List(*filter);
  if (!page.ok()) return ToGrpcStatus(page.status());
  for (const Job& job : page->jobs) *response->add_jobs() = fleetnav::ToProto(job);
  response->set_next_page_token(page->next_page_token);
  return grpc::Status::OK;
}

grpc::Status FleetServiceImpl::CancelJob(grpc::ServerContext*, const v1::CancelJobRequest* request,
                                         v1::CancelJobResponse* response) {
  absl::StatusOr<Job> job = jobs_->Cancel(request->job_id(), request->reason());
  if (!job.ok()) return ToGrpcStatus(job.status());
  *response->mutable_job() = fleetnav::ToProto(*job);
  return grpc::Status::OK;
}

grpc::Status FleetServiceImpl::PauseJob(grpc::ServerContext*, const v1::PauseJobRequest* request,
                                        v1::PauseJobResponse* response) {
  absl::StatusOr<Job> job = jobs_->Pause(request->job_id(), request->reason());
  if (!job.ok()) return ToGrpcStatus(job.status());
  *response->mutable_job() = fleetnav::ToProto(*job);
  return grpc::Status::OK;
}

grpc::Status FleetServiceImpl::ResumeJob(grpc::ServerContext*, const v1::ResumeJobRequest* request,
                                         v1::ResumeJobResponse* response) {
  absl::StatusOr<Job> job = jobs_->Resume(request->job_id());
  if (!job.ok()) return ToGrpcStatus(job.status());
  *response->mutable_job() = fleetnav::ToProto(*job);
  return grpc::Status::OK;
}

grpc::Status FleetServiceImpl::PlanPaths(grpc::ServerContext*, const v1::PlanPathsRequest* request,
                                         v1::PlanPathsResponse* response) {
  std::vector<TrafficAgent> agents;
  for (int i = 0; i < request->agents_size(); ++i) {
    absl::StatusOr<TrafficAgent> agent =
        FromProto(request->agents(i), absl::StrCat("agents[", i, "]"));
    if (!agent.ok()) return ToGrpcStatus(agent.status());
    agents.push_back(*std::move(agent));
  }
  const double time_limit_s = request->time_limit_s() == 0.0 ? 1.0 : request->time_limit_s();
  absl::StatusOr<TrafficPlan> plan =
      traffic_->Plan(request->map_id(), request->map_version(), agents, time_limit_s);
  if (!plan.ok()) return ToGrpcStatus(plan.status());
  *response = ToProto(*plan, agents);
  return grpc::Status::OK;
}

}  // namespace fleetnav::server
