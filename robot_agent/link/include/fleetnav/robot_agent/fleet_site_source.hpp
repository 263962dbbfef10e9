#pragma once

#include <grpcpp/channel.h>

#include <memory>
#include <string>

#include "fleetnav/robot_agent/site_source.hpp"
#include "fleetnav/v1/fleet_service.grpc.pb.h"

namespace fleetnav::agent {

/// SiteSource over fleetnavd's FleetService: GetMap and GetMarkerSet at the assignment's exact
/// versions, each call with a deadline. Thread-safe (gRPC stubs are).
class FleetSiteSource final : public SiteSource {
 public:
  explicit FleetSiteSource(std::shared_ptr<grpc::Channel> channel, double timeout_s = 10.0);
  absl::StatusOr<SiteData> Load(const std::string& map_id, uint32_t map_version,
                                uint32_t marker_set_version) override;
  absl::StatusOr<std::optional<ZoneSet>> LoadZones(const std::string& map_id,
                                                   uint32_t zone_set_version) override;

 private:
  std::unique_ptr<v1::FleetService::Stub> stub_;
  double timeout_s_;
};

}  // namespace fleetnav::agent
