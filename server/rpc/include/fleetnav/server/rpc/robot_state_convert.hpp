#pragma once

#include "fleetnav/server/fleet_registry.hpp"
#include "fleetnav/v1/types.pb.h"

namespace fleetnav::server {

/// The wire form of a registry record.
v1::RobotState ToProto(const RobotRecord& record);

}  // namespace fleetnav::server
