#include <cmath>
#include <nlohmann/json.hpp>
#include <ostream>

#include "absl/strings/str_format.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/scenario/scenario_runner.hpp"

namespace fleetnav::scenario {

void PrintReport(const ScenarioReport& report, std::ostream& out) {
  out << absl::StrFormat("scenario %s, seed %u: %s\n", report.name, report.seed,
                         report.passed ? "PASSED" : "FAILED");
  out << absl::StrFormat("%-16s %-10s %-8s %-10s %-10s %s\n", "JOB", "ID", "ROBOT", "STATE",
                         "EXPECTED", "REASON");
  for (const JobOutcome& job : report.jobs) {
    out << absl::StrFormat("%-16s %-10s %-8s %-10s %-10s %s\n", job.name, job.job_id, job.robot_id,
                           job.state, job.expected, job.reason);
  }
  out << absl::StrFormat("%-8s %5s %11s %10s %15s %9s  %s\n", "ROBOT", "JOBS", "DISTANCE_M",
                         "WAITING_S", "MAX_LOC_ERR_M", "CONTACTS", "TRUE END POSE");
  for (const RobotFigures& robot : report.robots) {
    out << absl::StrFormat("%-8s %5d %11.2f %10.1f %15.3f %9d  (%.2f, %.2f, %.1f°)\n",
                           robot.robot_id, robot.jobs, robot.distance_m, robot.waiting_s,
                           robot.max_loc_error_m, robot.contacts, robot.final_pose.x_m(),
                           robot.final_pose.y_m(), robot.final_pose.yaw_rad() * 180.0 / kPi);
  }
  for (const RobotFigures& robot : report.robots) {
    for (const std::string& wait : robot.waits) {
      out << "  " << robot.robot_id << " waited: " << wait << "\n";
    }
  }
  out << absl::StrFormat(
      "contacts %d, min separation %.3f m, sim time %.1f s, wall time %.1f s, real-time factor "
      "%.1f, waiting share %.1f %%\n",
      report.contacts, report.min_separation_m, report.sim_time_s, report.wall_time_s,
      report.real_time_factor, 100.0 * report.waiting_share);
  out << absl::StrFormat(
      "waiting %.1f s in all; the work would have ended at %.1f s had no robot been held "
      "(no-coordination lower bound); the fleet stood still at most %.1f s with work to do\n",
      [&] {
        double total = 0.0;
        for (const RobotFigures& robot : report.robots) total += robot.waiting_s;
        return total;
      }(),
      report.no_wait_end_s, report.longest_standstill_s);
  if (report.no_go_entries > 0 || !report.max_speed_in_zone_mps.empty() ||
      !report.max_robots_in_zone.empty()) {
    out << absl::StrFormat("zones: %d no-go entr%s", report.no_go_entries,
                           report.no_go_entries == 1 ? "y" : "ies");
    for (const auto& [zone, speed_mps] : report.max_speed_in_zone_mps) {
      out << absl::StrFormat(", %s at most %.3f m/s", zone, speed_mps);
    }
    for (const auto& [zone, robots] : report.max_robots_in_zone) {
      out << absl::StrFormat(", %s at most %d robot%s at once", zone, robots,
                             robots == 1 ? "" : "s");
    }
    if (report.over_capacity_entries > 0) {
      out << absl::StrFormat(", %d entr%s into a full zone", report.over_capacity_entries,
                             report.over_capacity_entries == 1 ? "y" : "ies");
    }
    out << "\n";
  }
  if (report.stops_made > 0) {
    out << absl::StrFormat(
        "stops: %d made; stopped robots moved at most %.3f m; %d entr%s into stopped zones\n",
        report.stops_made, report.max_motion_while_stopped_m, report.stopped_zone_entries,
        report.stopped_zone_entries == 1 ? "y" : "ies");
  }
  const double per_sim_s = report.sim_time_s > 0.0 ? 1.0 / report.sim_time_s : 0.0;
  out << absl::StrFormat(
      "CPU: fleetnavd %.1f s (%.4f per sim-s), simulator %.1f s, agents %.1f s (%.4f per robot "
      "and sim-s)\n",
      report.server_cpu_s, report.server_cpu_s * per_sim_s, report.sim_cpu_s, report.agents_cpu_s,
      report.robots.empty() ? 0.0 : report.agents_cpu_s * per_sim_s / report.robots.size());
  out << absl::StrFormat(
      "fleetnavd dispatch passes that assigned jobs: %d, p50 %.2f ms, p99 %.2f ms, max %.2f ms\n",
      report.assigning_passes, report.assigning_pass_ms_p50, report.assigning_pass_ms_p99,
      report.assigning_pass_ms_max);
  out << absl::StrFormat(
      "of which assigned one job (replanning when a job is added): %d, p50 %.2f ms, p99 %.2f "
      "ms, max %.2f ms\n",
      report.one_job_passes, report.one_job_pass_ms_p50, report.one_job_pass_ms_p99,
      report.one_job_pass_ms_max);
  out << absl::StrFormat(
      "  the same in the dispatcher thread's CPU time: p50 %.2f ms, p99 %.2f ms, max %.2f ms\n",
      report.one_job_pass_cpu_ms_p50, report.one_job_pass_cpu_ms_p99,
      report.one_job_pass_cpu_ms_max);
  out << absl::StrFormat(
      "traffic searches on their own thread: %d, CPU p50 %.2f ms, p99 %.2f ms, max %.2f ms\n",
      report.traffic_searches, report.traffic_search_cpu_ms_p50, report.traffic_search_cpu_ms_p99,
      report.traffic_search_cpu_ms_max);
  if (!report.failovers_s.empty()) {
    out << "leader failovers (kill to the successor leading):";
    for (const double seconds : report.failovers_s) out << absl::StrFormat(" %.2f s", seconds);
    out << "\n";
  }
  for (const std::string& failure : report.failures) out << "FAILED: " << failure << "\n";
  if (!report.work_dir.empty()) out << "logs and recordings kept in " << report.work_dir << "\n";
}

std::string ReportJson(const ScenarioReport& report) {
  nlohmann::json jobs = nlohmann::json::array();
  for (const JobOutcome& job : report.jobs) {
    jobs.push_back({{"name", job.name},
                    {"job_id", job.job_id},
                    {"robot_id", job.robot_id},
                    {"state", job.state},
                    {"expected", job.expected},
                    {"reason", job.reason},
                    {"end_sim_s", job.end_sim_s}});
  }
  nlohmann::json robots = nlohmann::json::array();
  for (const RobotFigures& robot : report.robots) {
    robots.push_back({{"robot_id", robot.robot_id},
                      {"jobs", robot.jobs},
                      {"distance_m", robot.distance_m},
                      {"waiting_s", robot.waiting_s},
                      {"max_loc_error_m", robot.max_loc_error_m},
                      {"contacts", robot.contacts},
                      {"final_pose",
                       {{"x_m", robot.final_pose.x_m()},
                        {"y_m", robot.final_pose.y_m()},
                        {"yaw_rad", robot.final_pose.yaw_rad()}}},
                      {"waits", robot.waits}});
  }
  nlohmann::json out = {{"name", report.name},
                        {"seed", report.seed},
                        {"passed", report.passed},
                        {"failures", report.failures},
                        {"jobs", jobs},
                        {"robots", robots},
                        {"contacts", report.contacts},
                        {"min_separation_m", report.min_separation_m},
                        {"sim_time_s", report.sim_time_s},
                        {"wall_time_s", report.wall_time_s},
                        {"real_time_factor", report.real_time_factor},
                        {"waiting_share", report.waiting_share},
                        {"no_wait_end_s", report.no_wait_end_s},
                        {"longest_standstill_s", report.longest_standstill_s},
                        {"no_go_entries", report.no_go_entries},
                        {"max_speed_in_zone_mps", report.max_speed_in_zone_mps},
                        {"max_robots_in_zone", report.max_robots_in_zone},
                        {"over_capacity_entries", report.over_capacity_entries},
                        {"stops_made", report.stops_made},
                        {"max_motion_while_stopped_m", report.max_motion_while_stopped_m},
                        {"stopped_zone_entries", report.stopped_zone_entries},
                        {"server_cpu_s", report.server_cpu_s},
                        {"sim_cpu_s", report.sim_cpu_s},
                        {"agents_cpu_s", report.agents_cpu_s},
                        {"assigning_passes", report.assigning_passes},
                        {"assigning_pass_ms_p50", report.assigning_pass_ms_p50},
                        {"assigning_pass_ms_p99", report.assigning_pass_ms_p99},
                        {"assigning_pass_ms_max", report.assigning_pass_ms_max},
                        {"one_job_passes", report.one_job_passes},
                        {"one_job_pass_ms_p50", report.one_job_pass_ms_p50},
                        {"one_job_pass_ms_p99", report.one_job_pass_ms_p99},
                        {"one_job_pass_ms_max", report.one_job_pass_ms_max},
                        {"one_job_pass_cpu_ms_p50", report.one_job_pass_cpu_ms_p50},
                        {"one_job_pass_cpu_ms_p99", report.one_job_pass_cpu_ms_p99},
                        {"one_job_pass_cpu_ms_max", report.one_job_pass_cpu_ms_max},
                        {"traffic_searches", report.traffic_searches},
                        {"traffic_search_cpu_ms_p50", report.traffic_search_cpu_ms_p50},
                        {"traffic_search_cpu_ms_p99", report.traffic_search_cpu_ms_p99},
                        {"traffic_search_cpu_ms_max", report.traffic_search_cpu_ms_max},
                        {"failovers_s", report.failovers_s}};
  if (!report.work_dir.empty()) out["work_dir"] = report.work_dir;
  return out.dump();
}

}  // namespace fleetnav::scenario
