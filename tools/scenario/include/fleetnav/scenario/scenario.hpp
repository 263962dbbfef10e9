#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/zone.hpp"

namespace fleetnav::scenario {

/// A robot of the world that the scenario runs an agent for.
struct ScenarioRobot {
  std::string robot_id;
  std::string kind_name;  ///< from the world
  Pose2 initial_pose;     ///< the agent's --initial-pose (default: the world's spawn pose)
  int particles = 2000;
};

/// A job submitted at a sim time: a route by name, or a goal on the scenario's map.
struct ScenarioJob {
  std::string name;  ///< the scenario's name for it (expectations use it)
  std::string route;
  std::optional<Pose2> goal;
  std::string robot_id;  ///< empty: any capable robot
  int priority = 0;
  double at_s = 0.0;
};

enum class ScenarioFaultType {
  kKillAgent,   ///< SIGKILL the robot's agent; restarted restart_after_s later (wall time)
  kKillServer,  ///< SIGKILL fleetnavd (the first replica); restarted on the same database and port
  kKillLeader,  ///< SIGKILL the replica leading the site; restarted as a follower
  kCutLink,     ///< the robot's link to fleetnavd cut for duration_s (sim time), then restored
  kSimFault,    ///< a simulator fault (SimService.InjectFault)
  kStopZone,    ///< an operator stops a zone (fleetnavctl stop) for duration_s (0: to the end)
  kStopAll,     ///< an operator stops the whole fleet for duration_s (0: to the end)
  kPutZones,    ///< an operator puts a new version of the map's zones (fleetnavctl zones put)
};

struct ScenarioFault {
  ScenarioFaultType type = ScenarioFaultType::kSimFault;
  std::string sim_type;  ///< for kSimFault: slow_down, wheel_slip, sensor_dropout, ...
  double at_s = 0.0;
  std::string robot_id;
  double restart_after_s = 1.0;
  double duration_s = 0.0;
  double factor = 1.0;
  std::string sensor;
  std::string zone;                               ///< kStopZone: a zone in force then
  std::string file;                               ///< kPutZones: the zone YAML, resolved
  std::optional<ZoneSet> zones;                   ///< kPutZones: that file's zones
  std::optional<std::pair<Pose2, Pose2>> region;  ///< min and max corners (yaw unused)
};

/// What must hold at the end for the run to pass.
struct ScenarioExpectations {
  std::string all_jobs = "succeeded";             ///< every job's end state …
  std::map<std::string, std::string> job_states;  ///< … unless named here
  int max_contacts = 0;
  std::optional<double> min_separation_m;
  /// The fleet may stand still (no robot moving, a job unfinished) at most this long (sim s).
  std::optional<double> max_standstill_s;
  double deadline_s = 600.0;  ///< sim time by which every job has ended
  /// Sim time each named robot may be held by traffic coordination at most.
  std::map<std::string, double> max_waiting_s;
  /// Entries of true footprints into no-go zones (ZoneTruth) at most; 0 unless said when the
  /// scenario has no-go zones.
  std::optional<int> max_no_go_entries;
  /// Per zone: the highest true speed (m/s) of a robot whose centre is inside it.
  std::map<std::string, double> max_speed_in_zone_mps;
  /// Entries of true footprints into one-at-a-time zones that already held as many robots as
  /// they admit (ZoneTruth) at most; 0 unless said when the scenario has such zones.
  std::optional<int> max_over_capacity_entries;
  /// With stops: how far a stopped robot may move once the stop has had 2 s of sim time to
  /// reach it (StopTruth; default 0.05 m), and entries into stopped zones (default 0).
  std::optional<double> max_motion_while_stopped_m;
};

/// A multi-robot scenario (docs/scenarios.md). Paths are resolved against the file's folder.
struct Scenario {
  std::string name;
  std::string path;        ///< the scenario file
  std::string world_path;  ///< the world YAML
  std::string map_id;      ///< the world's name: its exported map is uploaded under it
  std::vector<std::string> route_paths;
  /// `zones`: a zone YAML put on the world's map before the routes; empty: none.
  std::string zones_path;
  std::optional<ZoneSet> zones;
  unsigned seed = 1;
  double real_time_factor = 0.0;
  /// fleetnavd replicas sharing the run's PostgreSQL database (1: one plain fleetnavd).
  int replicas = 1;
  /// `tls_dev_certs`: serve TLS with robot certificates and operator tokens, from a
  /// development PKI this script (deploy/certs/make-dev-certs) makes for the run; empty:
  /// plaintext (--insecure).
  std::string tls_dev_certs;
  std::vector<ScenarioRobot> robots;
  std::vector<ScenarioJob> jobs;
  std::vector<ScenarioFault> faults;
  ScenarioExpectations expect;
};

/// Parses a scenario file and checks it against its world: unknown keys, impossible times
/// (negative, or after the deadline), robots the world does not hold, routes or jobs named
/// twice are InvalidArgument naming the file and the key (e.g. "s.yaml: jobs[2].robot:
/// 'lely9' is not a robot of world barn").
absl::StatusOr<Scenario> LoadScenario(const std::string& path);

/// The zones in force when fault `fault_index` (< faults.size()) is injected: those of the last
/// put_zones fault injected before it (at an earlier time, or at the same time and earlier in
/// the list; faults are injected in that order), else the scenario's `zones`; null for none.
const ZoneSet* ZonesInForceAt(const Scenario& scenario, size_t fault_index);

}  // namespace fleetnav::scenario
