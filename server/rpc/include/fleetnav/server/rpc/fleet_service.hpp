#pragma once

#include "fleetnav/server/jobs/job_service.hpp"
#include "fleetnav/server/robots/fleet_registry.hpp"
#include "fleetnav/server/rpc/watch_hub.hpp"
#include "fleetnav/server/site/map_catalog.hpp"
#include "fleetnav/server/site/site_catalog.hpp"
#include "fleetnav/server/site/stop_control.hpp"
#include "fleetnav/server/site/zone_catalog.hpp"
#include "fleetnav/server/traffic/traffic_planner.hpp"
#include "fleetnav/v1/fleet_service.grpc.pb.h"

namespace fleetnav::server {

/// gRPC edge of FleetService: converts the request, calls a use case, converts the answer.
/// The watch streams (WatchFleet, WatchJob) are served by the WatchHub on the async API.
/// Thread-safe.
class FleetServiceImpl final : public FleetServiceBase {
 public:
  FleetServiceImpl(MapCatalog* maps, SiteCatalog* site, ZoneCatalog* zones, StopControl* stops,
                   JobService* jobs, TrafficPlanner* traffic, FleetRegistry* registry)
      : maps_(maps),
        site_(site),
        zones_(zones),
        stops_(stops),
        jobs_(jobs),
        traffic_(traffic),
        registry_(registry) {}

  grpc::Status PutMap(grpc::ServerContext* context, const v1::PutMapRequest* request,
                      v1::PutMapResponse* response) override;
  grpc::Status GetMap(grpc::ServerContext* context, const v1::GetMapRequest* request,
                      v1::GetMapResponse* response) override;
  grpc::Status ListMaps(grpc::ServerContext* context, const v1::ListMapsRequest* request,
                        v1::ListMapsResponse* response) override;
  grpc::Status DeleteMap(grpc::ServerContext* context, const v1::DeleteMapRequest* request,
                         v1::DeleteMapResponse* response) override;
  grpc::Status ListRobots(grpc::ServerContext* context, const v1::ListRobotsRequest* request,
                          v1::ListRobotsResponse* response) override;
  grpc::Status GetRobot(grpc::ServerContext* context, const v1::GetRobotRequest* request,
                        v1::GetRobotResponse* response) override;
  grpc::Status ForgetRobot(grpc::ServerContext* context, const v1::ForgetRobotRequest* request,
                           v1::ForgetRobotResponse* response) override;
  grpc::Status PutMarkerSet(grpc::ServerContext* context, const v1::PutMarkerSetRequest* request,
                            v1::PutMarkerSetResponse* response) override;
  grpc::Status GetMarkerSet(grpc::ServerContext* context, const v1::GetMarkerSetRequest* request,
                            v1::GetMarkerSetResponse* response) override;
  grpc::Status DeleteMarkerSet(grpc::ServerContext* context,
                               const v1::DeleteMarkerSetRequest* request,
                               v1::DeleteMarkerSetResponse* response) override;
  grpc::Status PutZones(grpc::ServerContext* context, const v1::PutZonesRequest* request,
                        v1::PutZonesResponse* response) override;
  grpc::Status GetZones(grpc::ServerContext* context, const v1::GetZonesRequest* request,
                        v1::GetZonesResponse* response) override;
  grpc::Status ListZones(grpc::ServerContext* context, const v1::ListZonesRequest* request,
                         v1::ListZonesResponse* response) override;
  grpc::Status DeleteZones(grpc::ServerContext* context, const v1::DeleteZonesRequest* request,
                           v1::DeleteZonesResponse* response) override;
  grpc::Status StopRobots(grpc::ServerContext* context, const v1::StopRobotsRequest* request,
                          v1::StopRobotsResponse* response) override;
  grpc::Status ResumeRobots(grpc::ServerContext* context, const v1::ResumeRobotsRequest* request,
                            v1::ResumeRobotsResponse* response) override;
  grpc::Status ListStops(grpc::ServerContext* context, const v1::ListStopsRequest* request,
                         v1::ListStopsResponse* response) override;
  grpc::Status PutRoute(grpc::ServerContext* context, const v1::PutRouteRequest* request,
                        v1::PutRouteResponse* response) override;
  grpc::Status GetRoute(grpc::ServerContext* context, const v1::GetRouteRequest* request,
                        v1::GetRouteResponse* response) override;
  grpc::Status ListRoutes(grpc::ServerContext* context, const v1::ListRoutesRequest* request,
                          v1::ListRoutesResponse* response) override;
  grpc::Status DeleteRoute(grpc::ServerContext* context, const v1::DeleteRouteRequest* request,
                           v1::DeleteRouteResponse* response) override;
  grpc::Status SubmitJob(grpc::ServerContext* context, const v1::SubmitJobRequest* request,
                         v1::SubmitJobResponse* response) override;
  grpc::Status GetJob(grpc::ServerContext* context, const v1::GetJobRequest* request,
                      v1::GetJobResponse* response) override;
  grpc::Status ListJobs(grpc::ServerContext* context, const v1::ListJobsRequest* request,
                        v1::ListJobsResponse* response) override;
  grpc::Status CancelJob(grpc::ServerContext* context, const v1::CancelJobRequest* request,
                         v1::CancelJobResponse* response) override;
  grpc::Status PauseJob(grpc::ServerContext* context, const v1::PauseJobRequest* request,
                        v1::PauseJobResponse* response) override;
  grpc::Status ResumeJob(grpc::ServerContext* context, const v1::ResumeJobRequest* request,
                         v1::ResumeJobResponse* response) override;
  grpc::Status PlanPaths(grpc::ServerContext* context, const v1::PlanPathsRequest* request,
                         v1::PlanPathsResponse* response) override;

 private:
  MapCatalog* maps_;
  SiteCatalog* site_;
  ZoneCatalog* zones_;
  StopControl* stops_;
  JobService* jobs_;
  TrafficPlanner* traffic_;
  FleetRegistry* registry_;
};

}  // namespace fleetnav::server
