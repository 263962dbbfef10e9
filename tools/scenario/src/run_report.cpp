#include <signal.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>

#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "absl/strings/strip.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/clock.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/proto/channel_credentials.hpp"
#include "fleetnav/proto/geometry_convert.hpp"
#include "fleetnav/proto/server_target.hpp"
#include "fleetnav/scenario/standstill.hpp"
#include "fleetnav/scenario/zone_truth.hpp"
#include "scenario_run.hpp"

namespace fleetnav::scenario::internal {

/// fleetnavd's exit line "N assigning dispatch passes, p50 X ms, p99 Y ms, max Z ms; M one-job
/// passes, p50 A ms, p99 B ms, max C ms; one-job pass CPU p50 D ms, p99 E ms, max F ms".
void ReadAssigningPasses(const std::string& log, ScenarioReport* report) {
  const size_t at = log.rfind(" assigning dispatch passes, ");
  if (at == std::string::npos) return;
  const size_t line = log.rfind(' ', at - 1);
  long long count = 0;
  double p50 = 0.0, p99 = 0.0, max = 0.0;
  if (std::sscanf(log.c_str() + line + 1,
                  "%lld assigning dispatch passes, p50 %lf ms, p99 %lf ms, max %lf ms", &count,
                  &p50, &p99, &max) == 4) {
    report->assigning_passes = count;
    report->assigning_pass_ms_p50 = p50;
    report->assigning_pass_ms_p99 = p99;
    report->assigning_pass_ms_max = max;
  }
  const size_t one = log.find(" one-job passes, ", at);
  if (one == std::string::npos) return;
  const size_t one_line = log.rfind(' ', one - 1);
  if (std::sscanf(log.c_str() + one_line + 1,
                  "%lld one-job passes, p50 %lf ms, p99 %lf ms, max %lf ms", &count, &p50, &p99,
                  &max) == 4) {
    report->one_job_passes = count;
    report->one_job_pass_ms_p50 = p50;
    report->one_job_pass_ms_p99 = p99;
    report->one_job_pass_ms_max = max;
  }
  const size_t cpu = log.find("one-job pass CPU ", one);
  if (cpu != std::string::npos &&
      std::sscanf(log.c_str() + cpu, "one-job pass CPU p50 %lf ms, p99 %lf ms, max %lf ms", &p50,
                  &p99, &max) == 3) {
    report->one_job_pass_cpu_ms_p50 = p50;
    report->one_job_pass_cpu_ms_p99 = p99;
    report->one_job_pass_cpu_ms_max = max;
  }
  const size_t searches = log.find(" traffic searches, CPU ", one);
  if (searches == std::string::npos) return;
  const size_t searches_line = log.rfind(' ', searches - 1);
  if (std::sscanf(log.c_str() + searches_line + 1,
                  "%lld traffic searches, CPU p50 %lf ms, p99 %lf ms, max %lf ms", &count, &p50,
                  &p99, &max) == 4) {
    report->traffic_searches = count;
    report->traffic_search_cpu_ms_p50 = p50;
    report->traffic_search_cpu_ms_p99 = p99;
    report->traffic_search_cpu_ms_max = max;
  }
}

namespace {

/// Rows "robot_id,kind,x,y,t_s" of a trajectory CSV, per robot, in file order.
struct Sample {
  double t_s, x, y, yaw_rad;
};
std::map<std::string, std::vector<Sample>> ReadTrajectories(const std::string& path) {
  std::map<std::string, std::vector<Sample>> out;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> f = absl::StrSplit(line, ',');
    if (f.size() < 5) continue;
    try {
      // The truth's sixth column is the yaw (estimates have none).
      out[f[0]].push_back({std::stod(f[4]), std::stod(f[2]), std::stod(f[3]),
                           f.size() > 5 ? std::stod(f[5]) : 0.0});
    } catch (const std::exception&) {
      continue;  // a header or a line cut by a kill
    }
  }
  return out;
}

}  // namespace

void Run::ReadGroundTruth(ScenarioReport* report) {
  grpc::ClientContext context;
  WithDeadline(&context);
  v1::GroundTruth truth;
  if (!simulator_->GetGroundTruth(&context, v1::GetGroundTruthRequest{}, &truth).ok()) {
    report->failures.push_back("the simulator's ground truth could not be read at the end");
    return;
  }
  report->min_separation_m = truth.min_separation_m();
  for (const v1::RobotGroundTruth& robot : truth.robots()) {
    if (figures_.count(robot.robot_id())) {
      RobotFigures& f = figures_[robot.robot_id()];
      f.contacts = static_cast<int>(robot.collisions());
      absl::StatusOr<Pose2> pose = fleetnav::FromProto(robot.pose());
      if (pose.ok()) f.final_pose = *pose;
    }
    report->contacts += static_cast<int>(robot.collisions());
  }
  for (const v1::Contact& contact : truth.contacts()) {  // oldest first
    auto it = figures_.find(contact.robot_id());
    if (it == figures_.end() || it->second.first_contact_s) continue;
    it->second.first_contact_s = static_cast<double>(contact.sim_time_ns()) * 1e-9;
    it->second.first_contact_with = contact.other();
  }
}

void Run::Finish(ScenarioReport* report) {
  // Figures from the recordings: the truth at 10 Hz of sim time, each agent's estimates.
  const auto truth = ReadTrajectories(Path("truth.csv"));
  for (auto& [id, f] : figures_) {
    const auto t = truth.find(id);
    if (t == truth.end()) continue;
    for (size_t i = 1; i < t->second.size(); ++i) {
      f.distance_m +=
          std::hypot(t->second[i].x - t->second[i - 1].x, t->second[i].y - t->second[i - 1].y);
    }
    const auto estimates = ReadTrajectories(Path(absl::StrCat("estimate-", id, ".csv")));
    const auto e = estimates.find(id);
    if (e == estimates.end()) continue;
    for (const Sample& est : e->second) {
      const auto near =
          std::lower_bound(t->second.begin(), t->second.end(), est.t_s,
                           [](const Sample& a, double time_s) { return a.t_s < time_s; });
      if (near == t->second.end() || std::abs(near->t_s - est.t_s) > 0.1) continue;
      f.max_loc_error_m = std::max(f.max_loc_error_m, std::hypot(near->x - est.x, near->y - est.y));
    }
  }
  for (const JobOutcome& job : jobs_) {
    if (IsEnd(job.state) && figures_.count(job.robot_id)) ++figures_[job.robot_id].jobs;
  }
  double waited_s = 0.0;
  for (auto& [id, f] : figures_) {
    report->robots.push_back(f);
    waited_s += f.waiting_s;
  }
  if (!figures_.empty() && report->sim_time_s > 0.0) {
    report->waiting_share = waited_s / (static_cast<double>(figures_.size()) * report->sim_time_s);
  }
  for (const RobotFigures& f : report->robots) {
    double last_end_s = -1.0;
    for (const JobOutcome& job : jobs_) {
      if (job.robot_id == f.robot_id) last_end_s = std::max(last_end_s, job.end_sim_s);
    }
    if (last_end_s >= 0.0) {
      report->no_wait_end_s = std::max(report->no_wait_end_s, last_end_s - f.waiting_s);
    }
  }
  {
    std::map<std::string, std::vector<TruthSample>> samples;
    for (const auto& [id, trajectory] : truth) {
      for (const Sample& s : trajectory) samples[id].push_back({s.t_s, s.x, s.y, s.yaw_rad});
    }
    std::map<std::string, Polygon2> footprints;
    for (const ScenarioRobot& robot : s_.robots) {
      if (absl::StatusOr<RobotModel> model = RobotModelByKind(robot.kind_name); model.ok()) {
        footprints[robot.robot_id] = model->footprint_m;
      }
    }
    if (s_.zones || !zones_put_.empty()) {
      // The scenario's zones from the start (none: an empty set), then each version put.
      std::vector<TimedZoneSet> versions{{0.0, s_.zones.value_or(ZoneSet{})}};
      versions.insert(versions.end(), zones_put_.begin(), zones_put_.end());
      const ZoneTruth zones = JudgeZonesOverTime(versions, samples, footprints);
      report->no_go_entries = zones.no_go_entries;
      report->first_no_go_entry = zones.first_no_go_entry;
      report->max_speed_in_zone_mps = zones.max_speed_in_zone_mps;
      report->max_robots_in_zone = zones.max_robots_in_zone;
      report->over_capacity_entries = zones.over_capacity_entries;
      report->first_over_capacity = zones.first_over_capacity;
    }
    if (!stop_windows_.empty()) {
      const StopTruth stops = JudgeStops(stop_windows_, samples, footprints);
      report->stops_made = static_cast<int>(stop_windows_.size());
      report->max_motion_while_stopped_m = stops.max_motion_while_stopped_m;
      report->worst_motion_while_stopped = stops.worst;
      report->stopped_zone_entries = stops.stopped_zone_entries;
    }
    std::vector<JobWindow> windows;
    for (size_t i = 0; i < jobs_.size(); ++i) {
      // A job refused at submission ended there.
      const double end_s =
          IsEnd(jobs_[i].state) && jobs_[i].end_sim_s < 0.0 ? s_.jobs[i].at_s : jobs_[i].end_sim_s;
      windows.push_back({s_.jobs[i].at_s, end_s});
    }
    report->longest_standstill_s = LongestStandstillS(samples, windows);
  }
  report->jobs = jobs_;
  // Expectations.
  for (const JobOutcome& job : jobs_) {
    if (job.state != job.expected) {
      report->failures.push_back(absl::StrCat("job ", job.name, " ended ", job.state, " (expected ",
                                              job.expected, ")",
                                              job.reason.empty() ? "" : ": " + job.reason));
    }
  }
  if (report->contacts > s_.expect.max_contacts) {
    // The earliest contact, to find it in the replay.
    const RobotFigures* earliest = nullptr;
    for (const RobotFigures& robot : report->robots) {
      if (robot.first_contact_s &&
          (earliest == nullptr || *robot.first_contact_s < *earliest->first_contact_s)) {
        earliest = &robot;
      }
    }
    const std::string first =
        earliest == nullptr
            ? ""
            : absl::StrFormat(": %s first touched %s at %.2f s of sim time", earliest->robot_id,
                              earliest->first_contact_with, *earliest->first_contact_s);
    report->failures.push_back(absl::StrCat(report->contacts, " contact episode(s) (at most ",
                                            s_.expect.max_contacts, " expected)", first));
  }
  if (s_.expect.max_standstill_s && report->longest_standstill_s > *s_.expect.max_standstill_s) {
    report->failures.push_back(absl::StrFormat(
        "the fleet stood still for %.1f s with jobs unfinished (at most %.1f s expected)",
        report->longest_standstill_s, *s_.expect.max_standstill_s));
  }
  if (s_.expect.min_separation_m && report->min_separation_m < *s_.expect.min_separation_m) {
    report->failures.push_back(absl::StrFormat("min separation %.3f m (at least %.3f m expected)",
                                               report->min_separation_m,
                                               *s_.expect.min_separation_m));
  }
  if (s_.expect.max_no_go_entries && report->no_go_entries > *s_.expect.max_no_go_entries) {
    report->failures.push_back(
        absl::StrCat(report->no_go_entries, " entry(ies) into no-go zones (at most ",
                     *s_.expect.max_no_go_entries, " expected): ", report->first_no_go_entry));
  }
  if (s_.expect.max_over_capacity_entries &&
      report->over_capacity_entries > *s_.expect.max_over_capacity_entries) {
    report->failures.push_back(absl::StrCat(
        report->over_capacity_entries, " entry(ies) into full one-at-a-time zones (at most ",
        *s_.expect.max_over_capacity_entries, " expected): ", report->first_over_capacity));
  }
  for (const std::string& failure : stop_failures_) report->failures.push_back(failure);
  if (s_.expect.max_motion_while_stopped_m &&
      report->max_motion_while_stopped_m > *s_.expect.max_motion_while_stopped_m) {
    report->failures.push_back(
        absl::StrFormat("a stopped robot moved %.3f m (at most %.3f m expected): %s",
                        report->max_motion_while_stopped_m, *s_.expect.max_motion_while_stopped_m,
                        report->worst_motion_while_stopped));
  }
  if (report->stopped_zone_entries > 0) {
    report->failures.push_back(
        absl::StrCat(report->stopped_zone_entries, " entry(ies) into a stopped zone (0 expected)"));
  }
  for (const auto& [zone, most_mps] : s_.expect.max_speed_in_zone_mps) {
    const auto driven = report->max_speed_in_zone_mps.find(zone);
    if (driven != report->max_speed_in_zone_mps.end() && driven->second > most_mps) {
      report->failures.push_back(
          absl::StrFormat("a robot drove %.3f m/s in zone '%s' (at most %.3f m/s expected)",
                          driven->second, zone, most_mps));
    }
  }
  for (const auto& [robot_id, most_s] : s_.expect.max_waiting_s) {
    const double waited_s = figures_[robot_id].waiting_s;
    if (waited_s > most_s) {
      report->failures.push_back(absl::StrFormat(
          "%s was held by traffic coordination for %.1f s (at most %.1f s expected)", robot_id,
          waited_s, most_s));
    }
  }
  if (report->sim_time_s >= s_.expect.deadline_s) {
    report->failures.push_back(
        absl::StrFormat("deadline of %.0f s of sim time reached", s_.expect.deadline_s));
  }
  report->passed = report->failures.empty();
  // The picture: map, true and estimated paths.
  if (!opt_.picture_path.empty()) {
    // Whole lines only: a process stopped mid-write leaves a cut last line.
    auto whole_lines = [](std::string text) { return text.substr(0, text.rfind('\n') + 1); };
    std::ofstream all(Path("trajectories.csv"));
    all << whole_lines(ReadWholeFile(Path("truth.csv")));
    for (const ScenarioRobot& robot : s_.robots) {
      all << whole_lines(ReadWholeFile(Path(absl::StrCat("estimate-", robot.robot_id, ".csv"))));
    }
    all.close();
    ChildProcess render({bin_.sim, "--world", s_.world_path, "--render", opt_.picture_path,
                         "--trajectories", Path("trajectories.csv")},
                        Path("render.out"), Path("render.log"));
    if (render.Wait(120.0) != 0) {
      report->failures.push_back(absl::StrCat("the picture was not drawn: ", render.Stderr()));
      report->passed = false;
    }
  }
  if (keep_) report->work_dir = work_;
}

}  // namespace fleetnav::scenario::internal
