#pragma once

#include <cstdint>
#include <string>

#include "absl/status/status.h"
#include "fleetnav/core/job.hpp"
#include "fleetnav/core/robot_state.hpp"
#include "fleetnav/server/jobs/job_service.hpp"
#include "fleetnav/server/robots/fleet_registry.hpp"
#include "fleetnav/server/robots/robot_mailbox.hpp"
#include "fleetnav/server/site/input_limits.hpp"
#include "fleetnav/server/site/map_catalog.hpp"
#include "fleetnav/server/site/site_catalog.hpp"
#include "fleetnav/server/site/stop_control.hpp"

namespace fleetnav::server {

/// The rules of a robot's session with fleetnavd, whatever carries it (the AgentService stream
/// is one transport): a hello is checked against the input limits before anything of it is
/// kept; the robot's jobs are settled before it shows as online, so that the dispatcher cannot
/// hand it new work in between; telemetry and job events count only from the robot's current
/// session (a replaced stream cannot end the job its robot now drives on the new one); leaving
/// ends only the session that left. It also tells every connected robot when a map or marker
/// set gets a new version. Thread-safe as the registry and the job service are.
class RobotSessions {
 public:
  RobotSessions(FleetRegistry* registry, JobService* jobs, RobotMailbox* robots, MapCatalog* maps,
                SiteCatalog* site, InputLimits limits)
      : registry_(registry),
        jobs_(jobs),
        robots_(robots),
        maps_(maps),
        site_(site),
        limits_(limits) {}

  /// ResourceExhausted naming the limit a hello goes beyond; nothing is kept.
  absl::Status CheckHello(const RobotIdentity& identity) const;
  /// Settles the robot's jobs (it resumes `resume_job_id`, or its others are failed or
  /// re-queued), registers it online and wakes the dispatcher. Returns the session, which
  /// replaces any earlier one of the robot. Call once its mailbox is open.
  uint64_t Open(const RobotIdentity& identity, const std::string& resume_job_id);
  /// Records telemetry of `session`; FailedPrecondition when the session was replaced.
  absl::Status RecordTelemetry(const std::string& robot_id, uint64_t session,
                               const Telemetry& telemetry);
  /// Hands a job event of `session` to the job service; FailedPrecondition when replaced.
  absl::Status RecordJobEvent(const std::string& robot_id, uint64_t session, const JobEvent& event);
  /// FailedPrecondition when `session` is not the robot's current one (it was replaced).
  absl::Status CheckSession(const std::string& robot_id, uint64_t session) const;
  /// The session ended (the robot hung up or its stream broke); the robot goes offline and its
  /// jobs wait for it, unless a newer session replaced this one.
  void Close(const std::string& robot_id, uint64_t session);
  /// Tells every connected robot the latest map and marker-set versions of `map_id`.
  void AnnounceSite(const std::string& map_id);
  /// Robots that connect are told the operators' stops in force. Set before sharing.
  void UseStops(StopControl* stops) { stops_ = stops; }
  /// The operators' stops in force, for a robot's welcome (none without UseStops).
  std::vector<RobotStop> StopsInForce();

 private:
  FleetRegistry* registry_;
  JobService* jobs_;
  RobotMailbox* robots_;
  MapCatalog* maps_;
  SiteCatalog* site_;
  const InputLimits limits_;
  StopControl* stops_ = nullptr;
};

}  // namespace fleetnav::server
