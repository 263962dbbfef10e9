#include "fleetnav/scenario/scenario.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <set>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/sim/world_description.hpp"

namespace fleetnav::scenario {
namespace {

/// Refuses keys of `node` outside `known`, naming the first unknown one.
absl::Status CheckKeys(const YAML::Node& node, const std::string& where,
                       const std::set<std::string>& known) {
  if (!node.IsMap()) return absl::InvalidArgumentError(absl::StrCat(where, ": expected a mapping"));
  for (const auto& entry : node) {
    const std::string key = entry.first.as<std::string>();
    if (!known.count(key)) {
      return absl::InvalidArgumentError(
          absl::StrCat(where.empty() ? key : absl::StrCat(where, ".", key),
                       ": unknown key (known: ", absl::StrJoin(known, ", "), ")"));
    }
  }
  return absl::OkStatus();
}

absl::StatusOr<double> Number(const YAML::Node& node, const std::string& where, double min_value) {
  double value = 0.0;
  try {
    value = node.as<double>();
  } catch (const YAML::Exception&) {
    return absl::InvalidArgumentError(absl::StrCat(where, ": expected a number"));
  }
  if (!std::isfinite(value) || value < min_value) {
    return absl::InvalidArgumentError(
        absl::StrCat(where, ": must be finite and >= ", min_value, ", got ", value));
  }
  return value;
}

absl::StatusOr<Pose2> PoseDeg(const YAML::Node& node, const std::string& where) {
  if (!node.IsSequence() || node.size() != 3) {
    return absl::InvalidArgumentError(absl::StrCat(where, ": expected [x, y, yaw_deg]"));
  }
  double v[3];
  for (int i = 0; i < 3; ++i) {
    ASSIGN_OR_RETURN(v[i], Number(node[i], where, -1e9));
  }
  return Pose2(v[0], v[1], DegToRad(v[2]));
}

absl::StatusOr<Pose2> Point(const YAML::Node& node, const std::string& where) {
  if (!node.IsSequence() || node.size() != 2) {
    return absl::InvalidArgumentError(absl::StrCat(where, ": expected [x, y]"));
  }
  ASSIGN_OR_RETURN(double x, Number(node[0], where, -1e9));
  ASSIGN_OR_RETURN(double y, Number(node[1], where, -1e9));
  return Pose2(x, y, 0.0);
}

std::string Text(const YAML::Node& node) { return node ? node.as<std::string>() : ""; }

bool IsJobState(const std::string& s) {
  return s == "succeeded" || s == "failed" || s == "cancelled";
}

absl::StatusOr<Scenario> Parse(const YAML::Node& root, const std::string& path) {
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  auto resolve = [&](const std::string& p) {
    return std::filesystem::path(p).is_absolute() ? p : (dir / p).lexically_normal().string();
  };
  RETURN_IF_ERROR(CheckKeys(root, "",
                            {"name", "world", "routes", "zones", "seed", "real_time_factor",
                             "replicas", "tls_dev_certs", "robots", "jobs", "faults", "expect"}));
  Scenario s;
  s.path = path;
  s.name =
      root["name"] ? root["name"].as<std::string>() : std::filesystem::path(path).stem().string();
  if (!root["world"]) return absl::InvalidArgumentError("world: missing (the world YAML file)");
  s.world_path = resolve(root["world"].as<std::string>());
  absl::StatusOr<sim::WorldDescription> world = sim::LoadWorld(s.world_path);
  if (!world.ok()) {
    return absl::InvalidArgumentError(absl::StrCat("world: ", world.status().message()));
  }
  s.map_id = world->name;
  if (root["seed"]) {
    ASSIGN_OR_RETURN(double seed, Number(root["seed"], "seed", 0));
    s.seed = static_cast<unsigned>(seed);
  }
  if (root["real_time_factor"]) {
    ASSIGN_OR_RETURN(s.real_time_factor, Number(root["real_time_factor"], "real_time_factor", 0));
  }
  if (root["replicas"]) {
    ASSIGN_OR_RETURN(const double replicas, Number(root["replicas"], "replicas", 1));
    if (replicas != static_cast<int>(replicas) || replicas > 9) {
      return absl::InvalidArgumentError("replicas: a whole number from 1 to 9");
    }
    s.replicas = static_cast<int>(replicas);
  }
  if (root["tls_dev_certs"]) {
    s.tls_dev_certs = resolve(root["tls_dev_certs"].as<std::string>());
    if (!std::filesystem::exists(s.tls_dev_certs)) {
      return absl::InvalidArgumentError(
          absl::StrCat("tls_dev_certs: no such file '", s.tls_dev_certs, "'"));
    }
  }
  // A zone file of the world's map, `where` naming the key for errors.
  const auto load_zones = [&](const std::string& file,
                              const std::string& where) -> absl::StatusOr<ZoneSet> {
    absl::StatusOr<ZoneSet> zones = LoadZoneSet(file);
    if (!zones.ok()) {
      return absl::InvalidArgumentError(absl::StrCat(where, ": ", zones.status().message()));
    }
    if (!zones->map_id.empty() && zones->map_id != s.map_id) {
      return absl::InvalidArgumentError(absl::StrCat(where, ": the file is of map '", zones->map_id,
                                                     "', the world is '", s.map_id, "'"));
    }
    zones->map_id = s.map_id;
    return zones;
  };
  if (root["zones"]) {
    s.zones_path = resolve(Text(root["zones"]));
    ASSIGN_OR_RETURN(s.zones, load_zones(s.zones_path, "zones"));
  }
  // Routes: loaded here so that a bad file is refused before anything starts.
  std::set<std::string> route_names;
  if (root["routes"]) {
    if (!root["routes"].IsSequence()) {
      return absl::InvalidArgumentError("routes: expected a list of route files");
    }
    for (size_t i = 0; i < root["routes"].size(); ++i) {
      const std::string where = absl::StrCat("routes[", i, "]");
      const std::string file = resolve(root["routes"][i].as<std::string>());
      absl::StatusOr<Route> route = LoadRoute(file);
      if (!route.ok()) {
        return absl::InvalidArgumentError(absl::StrCat(where, ": ", route.status().message()));
      }
      if (!route_names.insert(route->name).second) {
        return absl::InvalidArgumentError(
            absl::StrCat(where, ": route '", route->name, "' is named twice"));
      }
      s.route_paths.push_back(file);
    }
  }
  // Robots: of the world; all of them by default.
  std::map<std::string, sim::RobotSpawn> spawns;
  for (const sim::RobotSpawn& spawn : world->robots) spawns[spawn.robot_id] = spawn;
  if (root["robots"]) {
    if (!root["robots"].IsSequence()) return absl::InvalidArgumentError("robots: expected a list");
    for (size_t i = 0; i < root["robots"].size(); ++i) {
      const YAML::Node r = root["robots"][i];
      const std::string where = absl::StrCat("robots[", i, "]");
      RETURN_IF_ERROR(CheckKeys(r, where, {"id", "initial_pose", "particles"}));
      const std::string id = Text(r["id"]);
      auto spawn = spawns.find(id);
      if (spawn == spawns.end()) {
        return absl::InvalidArgumentError(
            absl::StrCat(where, ".id: '", id, "' is not a robot of world ", world->name));
      }
      ScenarioRobot robot{id, spawn->second.kind_name, spawn->second.pose, 2000};
      if (r["initial_pose"]) {
        ASSIGN_OR_RETURN(robot.initial_pose, PoseDeg(r["initial_pose"], where + ".initial_pose"));
      }
      if (r["particles"]) {
        ASSIGN_OR_RETURN(double n, Number(r["particles"], where + ".particles", 1));
        robot.particles = static_cast<int>(n);
      }
      for (const ScenarioRobot& other : s.robots) {
        if (other.robot_id == id) {
          return absl::InvalidArgumentError(absl::StrCat(where, ".id: '", id, "' is listed twice"));
        }
      }
      s.robots.push_back(robot);
    }
  } else {
    for (const sim::RobotSpawn& spawn : world->robots) {
      s.robots.push_back({spawn.robot_id, spawn.kind_name, spawn.pose, 2000});
    }
  }
  if (s.robots.empty()) return absl::InvalidArgumentError("robots: the world holds no robot");
  auto known_robot = [&](const std::string& id) {
    for (const ScenarioRobot& r : s.robots) {
      if (r.robot_id == id) return true;
    }
    return false;
  };
  if (s.zones && s.zones->HasKind(ZoneKind::kNoGo)) {
    s.expect.max_no_go_entries = 0;  // unless the expectations say otherwise
  }
  if (s.zones && s.zones->HasKind(ZoneKind::kOneAtATime)) s.expect.max_over_capacity_entries = 0;
  // Expectations first: the deadline bounds every time.
  if (const YAML::Node e = root["expect"]) {
    RETURN_IF_ERROR(
        CheckKeys(e, "expect",
                  {"jobs", "contacts", "min_separation_m", "deadline_s", "max_waiting_s",
                   "max_standstill_s", "no_go_entries", "max_speed_in_zone",
                   "max_motion_while_stopped_m", "over_capacity_entries"}));
    if (e["max_motion_while_stopped_m"]) {
      ASSIGN_OR_RETURN(
          s.expect.max_motion_while_stopped_m,
          Number(e["max_motion_while_stopped_m"], "expect.max_motion_while_stopped_m", 0));
    }
    if (e["no_go_entries"]) {
      ASSIGN_OR_RETURN(const double entries, Number(e["no_go_entries"], "expect.no_go_entries", 0));
      s.expect.max_no_go_entries = static_cast<int>(entries);
    }
    if (e["over_capacity_entries"]) {
      ASSIGN_OR_RETURN(const double entries,
                       Number(e["over_capacity_entries"], "expect.over_capacity_entries", 0));
      s.expect.max_over_capacity_entries = static_cast<int>(entries);
    }
    if (const YAML::Node speeds = e["max_speed_in_zone"]) {
      if (!speeds.IsMap()) {
        return absl::InvalidArgumentError("expect.max_speed_in_zone: expected {zone: m/s, ...}");
      }
      for (const auto& entry : speeds) {
        const std::string zone = entry.first.as<std::string>();
        const std::string where = absl::StrCat("expect.max_speed_in_zone.", zone);
        // The zone is looked for once the faults (and their put_zones) are read.
        ASSIGN_OR_RETURN(s.expect.max_speed_in_zone_mps[zone], Number(entry.second, where, 0));
      }
    }
    if (const YAML::Node waits = e["max_waiting_s"]) {
      if (!waits.IsMap()) {
        return absl::InvalidArgumentError("expect.max_waiting_s: expected {robot: seconds, ...}");
      }
      for (const auto& entry : waits) {
        const std::string robot = entry.first.as<std::string>();
        const std::string where = absl::StrCat("expect.max_waiting_s.", robot);
        if (!known_robot(robot)) {
          return absl::InvalidArgumentError(
              absl::StrCat(where, ": '", robot, "' is not a robot of the scenario"));
        }
        ASSIGN_OR_RETURN(s.expect.max_waiting_s[robot], Number(entry.second, where, 0));
      }
    }
    if (e["deadline_s"]) {
      ASSIGN_OR_RETURN(s.expect.deadline_s, Number(e["deadline_s"], "expect.deadline_s", 1e-9));
    }
    if (e["contacts"]) {
      ASSIGN_OR_RETURN(double c, Number(e["contacts"], "expect.contacts", 0));
      s.expect.max_contacts = static_cast<int>(c);
    }
    if (e["max_standstill_s"]) {
      ASSIGN_OR_RETURN(s.expect.max_standstill_s,
                       Number(e["max_standstill_s"], "expect.max_standstill_s", 0));
    }
    if (e["min_separation_m"]) {
      ASSIGN_OR_RETURN(s.expect.min_separation_m,
                       Number(e["min_separation_m"], "expect.min_separation_m", 0));
    }
    if (e["jobs"] && e["jobs"].IsScalar()) {
      s.expect.all_jobs = e["jobs"].as<std::string>();
      if (!IsJobState(s.expect.all_jobs)) {
        return absl::InvalidArgumentError(absl::StrCat("expect.jobs: '", s.expect.all_jobs,
                                                       "' is not an end state (succeeded, failed, "
                                                       "cancelled)"));
      }
    } else if (e["jobs"]) {
      for (const auto& entry : e["jobs"]) {
        const std::string job = entry.first.as<std::string>();
        const std::string state = entry.second.as<std::string>();
        if (!IsJobState(state)) {
          return absl::InvalidArgumentError(
              absl::StrCat("expect.jobs.", job, ": '", state, "' is not an end state"));
        }
        s.expect.job_states[job] = state;
      }
    }
  }
  auto check_time = [&](const YAML::Node& node,
                        const std::string& where) -> absl::StatusOr<double> {
    if (!node) return 0.0;
    ASSIGN_OR_RETURN(double t, Number(node, where, 0));
    if (t >= s.expect.deadline_s) {
      return absl::InvalidArgumentError(absl::StrCat(
          where, ": ", t, " s is not before the deadline ", s.expect.deadline_s, " s"));
    }
    return t;
  };
  if (!root["jobs"] || !root["jobs"].IsSequence() || root["jobs"].size() == 0) {
    return absl::InvalidArgumentError("jobs: expected a list of at least one job");
  }
  for (size_t i = 0; i < root["jobs"].size(); ++i) {
    const YAML::Node j = root["jobs"][i];
    const std::string where = absl::StrCat("jobs[", i, "]");
    RETURN_IF_ERROR(CheckKeys(j, where, {"id", "route", "goal", "robot", "priority", "at_s"}));
    ScenarioJob job;
    job.name = j["id"] ? j["id"].as<std::string>() : absl::StrCat("job-", i + 1);
    if (j["route"].IsDefined() == j["goal"].IsDefined()) {
      return absl::InvalidArgumentError(absl::StrCat(where, ": give either route or goal"));
    }
    if (j["route"]) {
      job.route = j["route"].as<std::string>();
      if (!route_names.count(job.route)) {
        return absl::InvalidArgumentError(
            absl::StrCat(where, ".route: '", job.route, "' is not in the scenario's routes"));
      }
    } else {
      ASSIGN_OR_RETURN(job.goal, PoseDeg(j["goal"], where + ".goal"));
    }
    job.robot_id = Text(j["robot"]);
    if (!job.robot_id.empty() && !known_robot(job.robot_id)) {
      return absl::InvalidArgumentError(
          absl::StrCat(where, ".robot: '", job.robot_id, "' is not a robot of the scenario"));
    }
    if (j["priority"]) job.priority = j["priority"].as<int>();
    ASSIGN_OR_RETURN(job.at_s, check_time(j["at_s"], where + ".at_s"));
    for (const ScenarioJob& other : s.jobs) {
      if (other.name == job.name) {
        return absl::InvalidArgumentError(
            absl::StrCat(where, ".id: '", job.name, "' is used twice"));
      }
    }
    s.jobs.push_back(job);
  }
  for (const auto& [name, state] : s.expect.job_states) {
    bool found = false;
    for (const ScenarioJob& job : s.jobs) found = found || job.name == name;
    if (!found) {
      return absl::InvalidArgumentError(absl::StrCat("expect.jobs.", name, ": no such job"));
    }
  }
  if (root["faults"]) {
    if (!root["faults"].IsSequence()) return absl::InvalidArgumentError("faults: expected a list");
    for (size_t i = 0; i < root["faults"].size(); ++i) {
      const YAML::Node f = root["faults"][i];
      const std::string where = absl::StrCat("faults[", i, "]");
      RETURN_IF_ERROR(CheckKeys(f, where,
                                {"type", "at_s", "robot", "restart_after_s", "duration_s", "factor",
                                 "sensor", "region", "zone", "file"}));
      ScenarioFault fault;
      const std::string type = Text(f["type"]);
      if (type == "kill_agent") {
        fault.type = ScenarioFaultType::kKillAgent;
      } else if (type == "kill_server") {
        fault.type = ScenarioFaultType::kKillServer;
      } else if (type == "kill_leader") {
        fault.type = ScenarioFaultType::kKillLeader;
        if (s.replicas < 2) {
          return absl::InvalidArgumentError(
              absl::StrCat(where, ".type: kill_leader needs replicas: 2 or more"));
        }
      } else if (type == "cut_link") {
        fault.type = ScenarioFaultType::kCutLink;
      } else if (type == "stop_zone") {
        fault.type = ScenarioFaultType::kStopZone;
        fault.zone = Text(f["zone"]);  // checked below, against the zones in force then
      } else if (type == "stop_all") {
        fault.type = ScenarioFaultType::kStopAll;
      } else if (type == "put_zones") {
        fault.type = ScenarioFaultType::kPutZones;
        if (!f["file"]) {
          return absl::InvalidArgumentError(
              absl::StrCat(where, ".file: put_zones needs a zone file"));
        }
        fault.file = resolve(Text(f["file"]));
        ASSIGN_OR_RETURN(fault.zones, load_zones(fault.file, where + ".file"));
      } else if (sim::FaultTypeByName(type).ok()) {
        fault.type = ScenarioFaultType::kSimFault;
        fault.sim_type = type;
      } else {
        return absl::InvalidArgumentError(absl::StrCat(
            where, ".type: unknown fault '", type,
            "' (known: kill_agent, kill_server, kill_leader, cut_link, stop_zone, stop_all, "
            "put_zones and "
            "the simulator's faults: "
            "hide_ultrasonic, "
            "remove_fence, remove_stripe, wheel_slip, sensor_dropout, slow_down)"));
      }
      ASSIGN_OR_RETURN(fault.at_s, check_time(f["at_s"], where + ".at_s"));
      fault.robot_id = Text(f["robot"]);
      if (!fault.robot_id.empty() && !known_robot(fault.robot_id)) {
        return absl::InvalidArgumentError(
            absl::StrCat(where, ".robot: '", fault.robot_id, "' is not a robot of the scenario"));
      }
      if ((fault.type == ScenarioFaultType::kKillAgent ||
           fault.type == ScenarioFaultType::kCutLink) &&
          fault.robot_id.empty()) {
        return absl::InvalidArgumentError(absl::StrCat(where, ".robot: ", type, " needs a robot"));
      }
      if (f["restart_after_s"]) {
        ASSIGN_OR_RETURN(fault.restart_after_s,
                         Number(f["restart_after_s"], where + ".restart_after_s", 0));
      }
      if (f["duration_s"]) {
        ASSIGN_OR_RETURN(fault.duration_s, Number(f["duration_s"], where + ".duration_s", 0));
      }
      if (f["factor"]) {
        ASSIGN_OR_RETURN(fault.factor, Number(f["factor"], where + ".factor", 0));
      }
      if (fault.type == ScenarioFaultType::kCutLink && !(fault.duration_s > 0.0)) {
        return absl::InvalidArgumentError(
            absl::StrCat(where, ".duration_s: cut_link needs a duration > 0 s (sim time)"));
      }
      fault.sensor = Text(f["sensor"]);
      if (f["region"]) {
        RETURN_IF_ERROR(CheckKeys(f["region"], where + ".region", {"min", "max"}));
        ASSIGN_OR_RETURN(Pose2 lo, Point(f["region"]["min"], where + ".region.min"));
        ASSIGN_OR_RETURN(Pose2 hi, Point(f["region"]["max"], where + ".region.max"));
        fault.region = std::make_pair(lo, hi);
      }
      s.faults.push_back(fault);
    }
  }
  for (size_t i = 0; i < s.faults.size(); ++i) {
    const ScenarioFault& f = s.faults[i];
    if (f.type != ScenarioFaultType::kStopZone) continue;
    const ZoneSet* zones = ZonesInForceAt(s, i);
    if (zones == nullptr || zones->Find(f.zone) == nullptr) {
      return absl::InvalidArgumentError(
          absl::StrCat("faults[", i, "].zone: '", f.zone, "' is not a zone in force at ", f.at_s,
                       " s (the scenario's `zones`, or the last put_zones file before the stop)"));
    }
  }
  const bool stops = std::any_of(s.faults.begin(), s.faults.end(), [](const ScenarioFault& f) {
    return f.type == ScenarioFaultType::kStopZone || f.type == ScenarioFaultType::kStopAll;
  });
  if (stops && !s.expect.max_motion_while_stopped_m) s.expect.max_motion_while_stopped_m = 0.05;
  for (const auto& [zone, most_mps] : s.expect.max_speed_in_zone_mps) {
    bool known = s.zones && s.zones->Find(zone) != nullptr;
    for (const ScenarioFault& f : s.faults) known = known || (f.zones && f.zones->Find(zone));
    if (!known) {
      return absl::InvalidArgumentError(
          absl::StrCat("expect.max_speed_in_zone.", zone, ": '", zone,
                       "' is not a zone of the scenario's `zones` or of a put_zones file"));
    }
  }
  // Zones put during the run are judged from their time on, with the same defaults.
  for (const ScenarioFault& f : s.faults) {
    if (!f.zones) continue;
    if (f.zones->HasKind(ZoneKind::kNoGo) && !s.expect.max_no_go_entries) {
      s.expect.max_no_go_entries = 0;
    }
    if (f.zones->HasKind(ZoneKind::kOneAtATime) && !s.expect.max_over_capacity_entries) {
      s.expect.max_over_capacity_entries = 0;
    }
  }
  return s;
}

}  // namespace

const ZoneSet* ZonesInForceAt(const Scenario& scenario, size_t fault_index) {
  const ScenarioFault& at = scenario.faults.at(fault_index);
  const ZoneSet* out = scenario.zones ? &*scenario.zones : nullptr;
  double put_at_s = -1.0;
  for (size_t i = 0; i < scenario.faults.size(); ++i) {
    const ScenarioFault& f = scenario.faults[i];
    const bool before = f.at_s < at.at_s || (f.at_s == at.at_s && i < fault_index);
    if (f.type == ScenarioFaultType::kPutZones && f.zones && before && f.at_s >= put_at_s) {
      out = &*f.zones;
      put_at_s = f.at_s;
    }
  }
  return out;
}

absl::StatusOr<Scenario> LoadScenario(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    return absl::NotFoundError(absl::StrCat("cannot open scenario file '", path, "'"));
  } catch (const YAML::Exception& e) {
    return absl::InvalidArgumentError(absl::StrCat(path, ": ", e.what()));
  }
  absl::StatusOr<Scenario> scenario;
  try {
    scenario = Parse(root, path);
  } catch (const YAML::Exception& e) {
    scenario = absl::InvalidArgumentError(e.what());
  }
  if (!scenario.ok()) {
    return absl::Status(scenario.status().code(),
                        absl::StrCat(path, ": ", scenario.status().message()));
  }
  return scenario;
}

}  // namespace fleetnav::scenario
