#include "fleetnav/server/robot_sessions.hpp"

namespace fleetnav::server {

absl::Status RobotSessions::CheckHello(const RobotIdentity& identity) const {
  return limits_.CheckIdentity(identity);
}

uint64_t RobotSessions::Open(const RobotIdentity& identity, const std::string& resume_job_id) {
  jobs_->OnRobotConnected(identity, resume_job_id);
  const uint64_t session = registry_->Connect(identity);
  jobs_->WakeDispatcher();  // an idle robot: there may be a job for it now
  return session;
}

std::vector<RobotStop> RobotSessions::StopsInForce() {
  if (stops_ == nullptr) return {};
  absl::StatusOr<std::vector<RobotStop>> stops = stops_->InForce();
  // A store that cannot be read now: the robot is told none, and hears of them with the next
  // change.
  return stops.ok() ? *std::move(stops) : std::vector<RobotStop>{};
}

absl::Status RobotSessions::RecordTelemetry(const std::string& robot_id, uint64_t session,
                                            const Telemetry& telemetry) {
  absl::Status recorded = registry_->RecordTelemetry(robot_id, session, telemetry);
  if (recorded.ok()) jobs_->OnTelemetry(robot_id, telemetry);
  return recorded;
}

absl::Status RobotSessions::RecordJobEvent(const std::string& robot_id, uint64_t session,
                                           const JobEvent& event) {
  if (absl::Status s = registry_->CheckSession(robot_id, session); !s.ok()) return s;
  jobs_->OnRobotEvent(robot_id, event);
  return absl::OkStatus();
}

absl::Status RobotSessions::CheckSession(const std::string& robot_id, uint64_t session) const {
  return registry_->CheckSession(robot_id, session);
}

void RobotSessions::Close(const std::string& robot_id, uint64_t session) {
  if (registry_->Disconnect(robot_id, session)) jobs_->OnRobotDisconnected(robot_id);
}

void RobotSessions::AnnounceSite(const std::string& map_id) {
  robots_->BroadcastMapUpdate(map_id, maps_->LatestVersion(map_id).value_or(0),
                              site_->LatestMarkerSetVersion(map_id));
}

}  // namespace fleetnav::server
