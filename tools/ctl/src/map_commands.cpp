#include <grpcpp/client_context.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "call_internal.hpp"
#include "fleetnav/core/map_io.hpp"
#include "fleetnav/ctl/commands.hpp"
#include "fleetnav/ctl/map_render.hpp"
#include "fleetnav/ctl/table.hpp"
#include "fleetnav/proto/grpc_status.hpp"
#include "fleetnav/proto/map_convert.hpp"
#include "fleetnav/proto/route_convert.hpp"
#include "fleetnav/v1/fleet_service.grpc.pb.h"

namespace fleetnav::ctl {
namespace {

absl::Status ReadFile(const std::string& path, std::string* contents) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return absl::NotFoundError(absl::StrCat("cannot read '", path, "'"));
  std::stringstream buffer;
  buffer << in.rdbuf();
  *contents = buffer.str();
  return absl::OkStatus();
}

}  // namespace

absl::Status ImportMap(const CommandContext& context, const std::string& map_id,
                       const std::string& yaml_path, const std::string& description) {
  v1::PutMapRequest request;
  request.set_map_id(map_id);
  request.set_description(description);
  std::string yaml;
  if (absl::Status s = ReadFile(yaml_path, &yaml); !s.ok()) return s;
  absl::StatusOr<MapServerMetadata> metadata = ParseMapServerYaml(yaml);
  if (!metadata.ok()) {
    return absl::Status(metadata.status().code(),
                        absl::StrCat(yaml_path, ": ", metadata.status().message()));
  }
  std::filesystem::path image = metadata->image;
  if (image.is_relative()) image = std::filesystem::path(yaml_path).parent_path() / image;
  std::string pgm;
  if (absl::Status s = ReadFile(image.string(), &pgm); !s.ok()) return s;
  request.mutable_map_server()->set_yaml(yaml);
  request.mutable_map_server()->set_pgm(pgm);

  auto stub = v1::FleetService::NewStub(context.channel);
  grpc::ClientContext rpc;
  PrepareCall(context, &rpc);
  v1::PutMapResponse response;
  if (absl::Status s = FromGrpcStatus(stub->PutMap(&rpc, request, &response)); !s.ok()) return s;
  if (context.json) {
    *context.out << nlohmann::json{{"map_id", response.map_id()}, {"version", response.version()}}
                 << '\n';
  } else {
    *context.out << "imported map '" << response.map_id() << "' as version " << response.version()
                 << '\n';
  }
  return absl::OkStatus();
}

absl::Status ListMaps(const CommandContext& context) {
  auto stub = v1::FleetService::NewStub(context.channel);
  grpc::ClientContext rpc;
  PrepareCall(context, &rpc);
  v1::ListMapsResponse response;
  if (absl::Status s = FromGrpcStatus(stub->ListMaps(&rpc, {}, &response)); !s.ok()) return s;
  if (context.json) {
    nlohmann::json maps = nlohmann::json::array();
    for (const v1::MapInfo& info : response.maps()) {
      maps.push_back({{"map_id", info.map_id()},
                      {"version", info.version()},
                      {"width", info.width()},
                      {"height", info.height()},
                      {"resolution_m", info.resolution_m()},
                      {"description", info.description()},
                      {"created_unix_ms", info.created_unix_ms()}});
    }
    *context.out << maps.dump() << '\n';
    return absl::OkStatus();
  }
  Table table({"MAP", "VERSION", "CELLS", "RESOLUTION", "SIZE", "DESCRIPTION"});
  for (const v1::MapInfo& info : response.maps()) {
    table.AddRow({info.map_id(), absl::StrCat(info.version()),
                  absl::StrCat(info.width(), "x", info.height()),
                  absl::StrFormat("%.3f m", info.resolution_m()),
                  absl::StrFormat("%.1f x %.1f m", info.width() * info.resolution_m(),
                                  info.height() * info.resolution_m()),
                  info.description()});
  }
  table.Print(*context.out);
  return absl::OkStatus();
}

absl::Status ExportMap(const CommandContext& context, const std::string& map_id, uint32_t version,
                       const std::string& yaml_path) {
  auto stub = v1::FleetService::NewStub(context.channel);
  grpc::ClientContext rpc;
  PrepareCall(context, &rpc);
  v1::GetMapRequest request;
  request.set_map_id(map_id);
  request.set_version(version);
  v1::GetMapResponse response;
  if (absl::Status s = FromGrpcStatus(stub->GetMap(&rpc, request, &response)); !s.ok()) return s;
  absl::StatusOr<OccupancyGrid> grid = FromProto(response.grid());
  if (!grid.ok()) return grid.status();
  if (absl::Status s = SaveMapServer(*grid, yaml_path); !s.ok()) return s;
  if (context.json) {
    *context.out << nlohmann::json{{"map_id", map_id},
                                   {"version", response.info().version()},
                                   {"yaml", yaml_path}}
                        .dump()
                 << '\n';
    return absl::OkStatus();
  }
  *context.out << "wrote map '" << map_id << "' version " << response.info().version() << " to "
               << yaml_path << '\n';
  return absl::OkStatus();
}

absl::Status DeleteMap(const CommandContext& context, const std::string& map_id) {
  auto stub = v1::FleetService::NewStub(context.channel);
  grpc::ClientContext rpc;
  PrepareCall(context, &rpc);
  v1::DeleteMapRequest request;
  request.set_map_id(map_id);
  v1::DeleteMapResponse response;
  if (absl::Status s = FromGrpcStatus(stub->DeleteMap(&rpc, request, &response)); !s.ok()) return s;
  if (context.json) {
    *context.out << nlohmann::json{{"deleted", map_id}}.dump() << '\n';
  } else {
    *context.out << "deleted map '" << map_id << "'\n";
  }
  return absl::OkStatus();
}

namespace {

absl::StatusOr<std::pair<OccupancyGrid, uint32_t>> FetchGrid(const CommandContext& context,
                                                             v1::FleetService::Stub& stub,
                                                             const std::string& map_id,
                                                             uint32_t version) {
  grpc::ClientContext rpc;
  PrepareCall(context, &rpc);
  v1::GetMapRequest request;
  request.set_map_id(map_id);
  request.set_version(version);
  v1::GetMapResponse response;
  if (absl::Status s = FromGrpcStatus(stub.GetMap(&rpc, request, &response)); !s.ok()) return s;
  absl::StatusOr<OccupancyGrid> grid = FromProto(response.grid());
  if (!grid.ok()) return grid.status();
  return std::make_pair(*std::move(grid), response.info().version());
}

/// The map's latest marker set, or none when the site has no markers.
absl::StatusOr<std::optional<MarkerSet>> FetchMarkers(const CommandContext& context,
                                                      v1::FleetService::Stub& stub,
                                                      const std::string& map_id) {
  grpc::ClientContext rpc;
  PrepareCall(context, &rpc);
  v1::GetMarkerSetRequest request;
  request.set_map_id(map_id);
  v1::GetMarkerSetResponse response;
  const absl::Status s = FromGrpcStatus(stub.GetMarkerSet(&rpc, request, &response));
  if (absl::IsNotFound(s)) return std::nullopt;
  if (!s.ok()) return s;
  absl::StatusOr<MarkerSet> markers = FromProto(response.marker_set());
  if (!markers.ok()) return markers.status();
  return *std::move(markers);
}

absl::StatusOr<std::vector<Route>> FetchRoutes(const CommandContext& context,
                                               v1::FleetService::Stub& stub,
                                               const std::string& map_id) {
  grpc::ClientContext rpc;
  PrepareCall(context, &rpc);
  v1::ListRoutesRequest request;
  request.set_map_id(map_id);
  v1::ListRoutesResponse response;
  if (absl::Status s = FromGrpcStatus(stub.ListRoutes(&rpc, request, &response)); !s.ok()) {
    return s;
  }
  std::vector<Route> routes;
  for (const v1::Route& wire : response.routes()) {
    absl::StatusOr<Route> route = FromProto(wire);
    if (!route.ok()) return route.status();
    routes.push_back(*std::move(route));
  }
  return routes;
}

}  // namespace

absl::Status RenderMap(const CommandContext& context, const std::string& map_id, uint32_t version,
                       const std::string& png_path, int pixels_per_cell) {
  auto stub = v1::FleetService::NewStub(context.channel);
  absl::StatusOr<std::pair<OccupancyGrid, uint32_t>> grid =
      FetchGrid(context, *stub, map_id, version);
  if (!grid.ok()) return grid.status();
  absl::StatusOr<std::optional<MarkerSet>> markers = FetchMarkers(context, *stub, map_id);
  if (!markers.ok()) return markers.status();
  absl::StatusOr<std::vector<Route>> routes = FetchRoutes(context, *stub, map_id);
  if (!routes.ok()) return routes.status();
  const SiteDrawing drawing{grid->first, *std::move(markers), *std::move(routes)};
  MapRenderParams params;
  params.pixels_per_cell = pixels_per_cell;
  if (absl::Status s = RenderSiteMapPng(drawing, png_path, params); !s.ok()) return s;
  const int scale = PixelsPerCell(drawing.grid, params);
  const int width_px = drawing.grid.width() * scale;
  const int height_px = drawing.grid.height() * scale;
  const size_t marker_count = drawing.markers ? drawing.markers->markers.size() : 0;
  if (context.json) {
    *context.out << nlohmann::json{{"map_id", map_id},
                                   {"version", grid->second},
                                   {"png", png_path},
                                   {"width_px", width_px},
                                   {"height_px", height_px},
                                   {"markers", marker_count},
                                   {"routes", drawing.routes.size()}}
                        .dump()
                 << '\n';
    return absl::OkStatus();
  }
  *context.out << "drew map '" << map_id << "' version " << grid->second << " (" << marker_count
               << " markers, " << drawing.routes.size() << " routes) to " << png_path << " ("
               << width_px << "x" << height_px << " px)\n";
  return absl::OkStatus();
}

}  // namespace fleetnav::ctl
