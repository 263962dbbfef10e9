#include "fleetnav/proto/telemetry_convert.hpp"

#include <cmath>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/echo_input.hpp"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/proto/geometry_convert.hpp"
#include "fleetnav/proto/robot_convert.hpp"

namespace fleetnav {
namespace {

bool IsValidRobotId(std::string_view id) {
  if (id.empty() || id.size() > 64) return false;
  for (char c : id) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '-' || c == '.';
    if (!ok) return false;
  }
  return true;
}

}  // namespace

// NavigationMode values line up one to one after the UNSPECIFIED slot.
v1::NavigationMode ToProto(NavigationMode mode) {
  return static_cast<v1::NavigationMode>(static_cast<int>(mode) + 1);
}

absl::StatusOr<NavigationMode> NavigationModeFromProto(int value) {
  if (value == v1::NAVIGATION_MODE_UNSPECIFIED) return NavigationMode::kIdle;
  if (value < 0 || value > v1::NAVIGATION_MODE_FAULT) {
    return absl::InvalidArgumentError(absl::StrCat("telemetry.mode: unknown value ", value));
  }
  return static_cast<NavigationMode>(value - 1);
}

v1::ConnectionState ToProto(ConnectionState state) {
  switch (state) {
    case ConnectionState::kOnline:
      return v1::CONNECTION_STATE_ONLINE;
    case ConnectionState::kStale:
      return v1::CONNECTION_STATE_STALE;
    case ConnectionState::kOffline:
      return v1::CONNECTION_STATE_OFFLINE;
  }
  return v1::CONNECTION_STATE_UNSPECIFIED;
}

v1::Telemetry ToProto(const Telemetry& telemetry) {
  v1::Telemetry out;
  out.set_stamp_ns(telemetry.stamp_ns);
  out.set_sequence(telemetry.sequence);
  *out.mutable_pose_in_map()->mutable_pose() = ToProto(telemetry.pose_in_map);
  for (double c : telemetry.covariance) out.mutable_pose_in_map()->add_covariance(c);
  *out.mutable_pose_in_odom() = ToProto(telemetry.pose_in_odom);
  out.mutable_velocity()->set_vx_mps(telemetry.velocity.vx_mps);
  out.mutable_velocity()->set_vy_mps(telemetry.velocity.vy_mps);
  out.mutable_velocity()->set_yaw_rate_radps(telemetry.velocity.yaw_rate_radps);
  out.set_mode(ToProto(telemetry.mode));
  out.mutable_localization()->set_confidence(telemetry.localization_confidence);
  out.mutable_localization()->set_lost(telemetry.localization_lost);
  out.set_battery_fraction(telemetry.battery_fraction);
  out.set_job_id(telemetry.job_id);
  out.set_action_index(telemetry.action_index);
  out.set_job_progress_fraction(telemetry.job_progress_fraction);
  out.set_action_progress_fraction(telemetry.action_progress_fraction);
  if (telemetry.carried_load_m) {
    out.mutable_carried_load_size()->set_x_m(telemetry.carried_load_m->x());
    out.mutable_carried_load_size()->set_y_m(telemetry.carried_load_m->y());
  }
  return out;
}

absl::StatusOr<Telemetry> FromProto(const v1::Telemetry& telemetry) {
  Telemetry out;
  out.stamp_ns = telemetry.stamp_ns();
  out.sequence = telemetry.sequence();
  ASSIGN_OR_RETURN(out.pose_in_map,
                   FromProto(telemetry.pose_in_map().pose(), "telemetry.pose_in_map"));
  const int covariance_size = telemetry.pose_in_map().covariance_size();
  if (covariance_size != 0 && covariance_size != 9) {
    return absl::InvalidArgumentError(absl::StrCat(
        "telemetry.pose_in_map.covariance: expected 9 values (3×3), got ", covariance_size));
  }
  for (int i = 0; i < covariance_size; ++i) {
    const double value = telemetry.pose_in_map().covariance(i);
    if (!std::isfinite(value)) {
      return absl::InvalidArgumentError(
          absl::StrCat("telemetry.pose_in_map.covariance[", i, "] must be finite"));
    }
    out.covariance[i] = value;
  }
  ASSIGN_OR_RETURN(out.pose_in_odom, FromProto(telemetry.pose_in_odom(), "telemetry.pose_in_odom"));
  out.velocity = {telemetry.velocity().vx_mps(), telemetry.velocity().vy_mps(),
                  telemetry.velocity().yaw_rate_radps()};
  if (!std::isfinite(out.velocity.vx_mps) || !std::isfinite(out.velocity.vy_mps) ||
      !std::isfinite(out.velocity.yaw_rate_radps)) {
    return absl::InvalidArgumentError("telemetry.velocity: components must be finite");
  }
  ASSIGN_OR_RETURN(out.mode, NavigationModeFromProto(telemetry.mode()));
  out.localization_confidence = telemetry.localization().confidence();
  out.localization_lost = telemetry.localization().lost();
  out.battery_fraction = telemetry.battery_fraction();
  out.job_id = telemetry.job_id();
  out.action_index = telemetry.action_index();
  out.job_progress_fraction = telemetry.job_progress_fraction();
  out.action_progress_fraction = telemetry.action_progress_fraction();
  if (!(out.action_progress_fraction >= 0.0 && out.action_progress_fraction <= 1.0)) {
    return absl::InvalidArgumentError(
        absl::StrCat("telemetry.action_progress_fraction: must be in [0, 1], got ",
                     out.action_progress_fraction));
  }
  if (telemetry.has_carried_load_size()) {
    const Eigen::Vector2d size_m(telemetry.carried_load_size().x_m(),
                                 telemetry.carried_load_size().y_m());
    if (!(size_m.x() > 0.0 && size_m.y() > 0.0 && size_m.allFinite())) {
      return absl::InvalidArgumentError(
          absl::StrCat("telemetry.carried_load_size: must be finite and > 0, got ", size_m.x(),
                       " × ", size_m.y(), " m"));
    }
    out.carried_load_m = size_m;
  }
  return out;
}

absl::StatusOr<RobotIdentity> FromProto(const v1::AgentHello& hello) {
  if (!IsValidRobotId(hello.robot_id())) {
    return absl::InvalidArgumentError(
        absl::StrCat("hello.robot_id: must be 1-64 characters of [A-Za-z0-9_.-], got '",
                     EchoInput(hello.robot_id()), "'"));
  }
  RobotIdentity out;
  out.robot_id = hello.robot_id();
  ASSIGN_OR_RETURN(out.model, FromProto(hello.model()));
  out.capabilities.assign(hello.capabilities().begin(), hello.capabilities().end());
  out.software_version = hello.software_version();
  out.segment_clearances = hello.segment_clearances();
  out.planned_paths = hello.planned_paths();
  return out;
}

v1::AgentHello ToProto(const RobotIdentity& identity) {
  v1::AgentHello out;
  out.set_robot_id(identity.robot_id);
  *out.mutable_model() = ToProto(identity.model);
  for (const std::string& capability : identity.capabilities) out.add_capabilities(capability);
  out.set_software_version(identity.software_version);
  out.set_segment_clearances(identity.segment_clearances);
  out.set_planned_paths(identity.planned_paths);
  return out;
}

v1::RobotState ToProto(const RobotRecord& record) {
  v1::RobotState out;
  out.set_robot_id(record.identity.robot_id);
  out.set_kind_name(record.identity.model.kind_name);
  *out.mutable_model() = ToProto(record.identity.model);
  for (const std::string& capability : record.identity.capabilities) {
    out.add_capabilities(capability);
  }
  out.set_software_version(record.identity.software_version);
  out.set_connection(ToProto(record.connection));
  if (record.last_telemetry) *out.mutable_last_telemetry() = ToProto(*record.last_telemetry);
  out.set_last_seen_ns(record.last_seen_ns);
  out.set_current_job_id(record.current_job_id);
  out.set_traffic_wait(record.traffic_wait);
  out.set_traffic_held_s(record.traffic_held_s);
  return out;
}

}  // namespace fleetnav
