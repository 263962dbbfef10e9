#pragma once

#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/map_info.hpp"
#include "fleetnav/core/traffic_plan.hpp"
#include "fleetnav/v1/fleet_service.pb.h"

namespace fleetnav {

/// Wire <-> domain for the site queries of FleetService: a map's info, and PlanPaths' agents
/// (FromProto names `field`.start or `field`.goal in InvalidArgument) and plan (paths in the
/// order of `agents`, whose robot ids they carry).
v1::MapInfo ToProto(const MapInfo& info);
absl::StatusOr<TrafficAgent> FromProto(const v1::PlanPathsRequest::Agent& agent,
                                       const std::string& field);
v1::PlanPathsResponse ToProto(const TrafficPlan& plan, const std::vector<TrafficAgent>& agents);

}  // namespace fleetnav
