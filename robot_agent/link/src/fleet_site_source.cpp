#include "fleetnav/robot_agent/fleet_site_source.hpp"

#include <grpcpp/client_context.h>

#include <chrono>

#include "absl/strings/str_cat.h"
#include "fleetnav/proto/grpc_status.hpp"
#include "fleetnav/proto/map_convert.hpp"
#include "fleetnav/proto/zone_convert.hpp"

namespace fleetnav::agent {
namespace {

void SetDeadline(grpc::ClientContext& context, double timeout_s) {
  context.set_deadline(std::chrono::system_clock::now() +
                       std::chrono::milliseconds(static_cast<int64_t>(timeout_s * 1000.0)));
}

}  // namespace

FleetSiteSource::FleetSiteSource(std::shared_ptr<grpc::Channel> channel, double timeout_s)
    : stub_(v1::FleetService::NewStub(channel)), timeout_s_(timeout_s) {}

absl::StatusOr<SiteData> FleetSiteSource::Load(const std::string& map_id, uint32_t map_version,
                                               uint32_t marker_set_version) {
  SiteData site;
  site.map_id = map_id;
  {
    grpc::ClientContext context;
    SetDeadline(context, timeout_s_);
    v1::GetMapRequest request;
    request.set_map_id(map_id);
    request.set_version(map_version);
    v1::GetMapResponse response;
    absl::Status status = FromGrpcStatus(stub_->GetMap(&context, request, &response));
    if (!status.ok()) return status;
    absl::StatusOr<OccupancyGrid> grid = FromProto(response.grid());
    if (!grid.ok()) return grid.status();
    site.map = std::make_shared<const OccupancyGrid>(*std::move(grid));
    site.map_version = response.info().version();
  }
  if (marker_set_version > 0) {
    grpc::ClientContext context;
    SetDeadline(context, timeout_s_);
    v1::GetMarkerSetRequest request;
    request.set_map_id(map_id);
    request.set_version(marker_set_version);
    v1::GetMarkerSetResponse response;
    absl::Status status = FromGrpcStatus(stub_->GetMarkerSet(&context, request, &response));
    if (!status.ok()) return status;
    absl::StatusOr<MarkerSet> markers = FromProto(response.marker_set());
    if (!markers.ok()) return markers.status();
    site.markers = *std::move(markers);
    site.marker_set_version = response.version();
  }
  return site;
}

absl::StatusOr<std::optional<ZoneSet>> FleetSiteSource::LoadZones(const std::string& map_id,
                                                                  uint32_t zone_set_version) {
  grpc::ClientContext context;
  SetDeadline(context, timeout_s_);
  v1::GetZonesRequest request;
  request.set_map_id(map_id);
  request.set_version(zone_set_version);
  v1::GetZonesResponse response;
  absl::Status status = FromGrpcStatus(stub_->GetZones(&context, request, &response));
  if (!status.ok()) return status;
  absl::StatusOr<ZoneSet> zones = FromProto(response.zone_set());
  if (!zones.ok()) return zones.status();
  return std::optional<ZoneSet>(*std::move(zones));
}

}  // namespace fleetnav::agent
