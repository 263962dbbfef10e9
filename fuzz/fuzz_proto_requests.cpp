// What fleetnavd converts from the wire: the bytes of each request (the first byte picks the
// message type) parsed as protobuf and converted to domain types, as the RPC edges do before
// anything is stored.
#include <cstddef>
#include <cstdint>

#include "fleetnav/proto/access_convert.hpp"
#include "fleetnav/proto/assignment_convert.hpp"
#include "fleetnav/proto/geometry_convert.hpp"
#include "fleetnav/proto/job_convert.hpp"
#include "fleetnav/proto/map_convert.hpp"
#include "fleetnav/proto/robot_convert.hpp"
#include "fleetnav/proto/route_convert.hpp"
#include "fleetnav/proto/telemetry_convert.hpp"
#include "fleetnav/proto/traffic_plan_convert.hpp"
#include "fleetnav/v1/access_service.pb.h"
#include "fleetnav/v1/agent_service.pb.h"
#include "fleetnav/v1/fleet_service.pb.h"

namespace v1 = fleetnav::v1;

namespace {

template <typename Message>
bool Parse(const uint8_t* data, size_t size, Message* message) {
  return message->ParseFromArray(data, static_cast<int>(size));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const uint8_t kind = data[0] % 9;
  ++data;
  --size;
  switch (kind) {
    case 0: {
      v1::PutMapRequest request;
      if (Parse(data, size, &request)) (void)fleetnav::FromProto(request.grid());
      break;
    }
    case 1: {
      v1::PutMarkerSetRequest request;
      if (Parse(data, size, &request)) (void)fleetnav::FromProto(request.marker_set());
      break;
    }
    case 2: {
      v1::PutRouteRequest request;
      if (Parse(data, size, &request)) (void)fleetnav::FromProto(request.route());
      break;
    }
    case 3: {
      v1::AgentMessage message;
      if (Parse(data, size, &message)) {
        if (message.has_hello()) (void)fleetnav::FromProto(message.hello());
        if (message.has_telemetry()) (void)fleetnav::FromProto(message.telemetry());
      }
      break;
    }
    case 4: {
      v1::SubmitJobRequest request;
      if (Parse(data, size, &request) && request.has_goal()) {
        (void)fleetnav::FromProto(request.goal().goal(), "goal.goal");
      }
      break;
    }
    case 5: {
      v1::PlanPathsRequest request;
      if (Parse(data, size, &request)) {
        for (const auto& agent : request.agents()) (void)fleetnav::FromProto(agent, "agents");
      }
      break;
    }
    case 6: {
      v1::ServerMessage message;
      if (Parse(data, size, &message)) {
        if (message.has_assignment()) (void)fleetnav::FromProto(message.assignment());
        if (message.has_command()) (void)fleetnav::FromProto(message.command());
      }
      break;
    }
    case 8: {
      v1::CreateTokenRequest request;
      if (Parse(data, size, &request)) (void)fleetnav::FromProto(request.role());
      break;
    }
    default: {
      v1::Job job;
      if (Parse(data, size, &job)) (void)fleetnav::FromProto(job);
      break;
    }
  }
  return 0;
}
