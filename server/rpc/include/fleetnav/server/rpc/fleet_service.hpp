#pragma once

#include <atomic>

#include "fleetnav/server/fleet_registry.hpp"
#include "fleetnav/server/map_catalog.hpp"
#include "fleetnav/v1/fleet_service.grpc.pb.h"

namespace fleetnav::server {

/// gRPC edge of FleetService: converts the request, calls a use case, converts the answer.
/// Maps and robots are served here; jobs, marker sets, routes and PlanPaths answer
/// UNIMPLEMENTED until the fleet-server issue lands them. Thread-safe.
class FleetServiceImpl final : public v1::FleetService::Service {
 public:
  FleetServiceImpl(MapCatalog* maps, FleetRegistry* registry, const std::atomic<bool>* stopping)
      : maps_(maps), registry_(registry), stopping_(stopping) {}

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
  grpc::Status WatchFleet(grpc::ServerContext* context, const v1::WatchFleetRequest* request,
                          grpc::ServerWriter<v1::FleetUpdate>* writer) override;

 private:
  MapCatalog* maps_;
  FleetRegistry* registry_;
  const std::atomic<bool>* stopping_;
};

}  // namespace fleetnav::server
