#include "fleetnav/server/rpc/robot_state_convert.hpp"

#include "fleetnav/proto/robot_convert.hpp"
#include "fleetnav/proto/telemetry_convert.hpp"

namespace fleetnav::server {

v1::RobotState ToProto(const RobotRecord& record) {
  v1::RobotState out;
  out.set_robot_id(record.identity.robot_id);
  out.set_kind_name(record.identity.model.kind_name);
  *out.mutable_model() = fleetnav::ToProto(record.identity.model);
  for (const std::string& capability : record.identity.capabilities) {
    out.add_capabilities(capability);
  }
  out.set_software_version(record.identity.software_version);
  out.set_connection(fleetnav::ToProto(record.connection));
  if (record.last_telemetry)
    *out.mutable_last_telemetry() = fleetnav::ToProto(*record.last_telemetry);
  out.set_last_seen_ns(record.last_seen_ns);
  out.set_current_job_id(record.current_job_id);
  out.set_traffic_wait(record.traffic_wait);
  return out;
}

}  // namespace fleetnav::server
