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
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/proto/channel_credentials.hpp"
#include "fleetnav/proto/geometry_convert.hpp"
#include "fleetnav/proto/server_target.hpp"
#include "scenario_run.hpp"

namespace fleetnav::scenario::internal {

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::string StateName(v1::JobState state) {
  std::string name = v1::JobState_Name(state);
  absl::AsciiStrToLower(&name);
  return name.rfind("job_state_", 0) == 0 ? name.substr(10) : name;
}

bool IsEnd(const std::string& state) {
  return state == "succeeded" || state == "failed" || state == "cancelled";
}

void WithDeadline(grpc::ClientContext* context, double seconds) {
  context->set_deadline(std::chrono::system_clock::now() +
                        std::chrono::milliseconds(static_cast<int64_t>(seconds * 1000)));
}

void Run::StartOutcomes() {
  jobs_.resize(s_.jobs.size());
  submitted_.assign(s_.jobs.size(), false);
  progress_.assign(s_.jobs.size(), 0.0);
  injected_.assign(s_.faults.size(), false);
  for (size_t i = 0; i < s_.jobs.size(); ++i) {
    jobs_[i].name = s_.jobs[i].name;
    jobs_[i].robot_id = s_.jobs[i].robot_id;
    jobs_[i].state = "waiting";
    const auto expected = s_.expect.job_states.find(s_.jobs[i].name);
    jobs_[i].expected =
        expected != s_.expect.job_states.end() ? expected->second : s_.expect.all_jobs;
  }
  for (const ScenarioRobot& robot : s_.robots) figures_[robot.robot_id].robot_id = robot.robot_id;
}

absl::StatusOr<double> Run::Drive(Clock::time_point wall_start) {
  // The simulation advances only as far as the runner asks (RunUntil), and everything the
  // runner does — submitting, injecting, restarting, polling — happens while it is held at an
  // exact tick: with the lockstep of agents and fleetnavd, a seed gives the same run every time.
  // Holds cost a drained pipeline each (agents, fleetnavd and the simulator all wait for the
  // runner), so the runner holds once a sim second besides its events: what it reports of the
  // time between holds — when jobs ended, how long robots stood held — fleetnavd recorded in
  // sim time.
  constexpr double kPollPeriodS = 1.0;
  double sim_s = 0.0;
  // Whether what is set for `at_s` is due at the held tick (tick times are whole nanoseconds).
  const auto due = [&](double at_s) { return sim_s + 1e-6 >= at_s; };
  while (true) {
    if (SecondsSince(wall_start) > opt_.wall_timeout_s) break;
    bool changed = false;
    // Restarts that are due.
    for (auto it = restarts_.begin(); it != restarts_.end();) {
      if (!due(it->due_sim_s)) {
        ++it;
        continue;
      }
      if (it->robot_id.empty()) {
        if (absl::Status st = StartServer(it->replica); !st.ok()) return st;
      } else {
        for (const ScenarioRobot& robot : s_.robots) {
          if (robot.robot_id != it->robot_id) continue;
          // Restarted where fleetnavd last saw it, as an operator would.
          if (absl::Status st = StartAgent(robot, LastKnownPose(robot)); !st.ok()) return st;
        }
      }
      it = restarts_.erase(it);
      changed = true;
    }
    if (!sim_->running()) break;
    for (auto it = link_restores_.begin(); it != link_restores_.end();) {
      if (!due(it->sim_s)) {
        ++it;
        continue;
      }
      links_.at(it->robot_id)->Restore();
      it = link_restores_.erase(it);
      changed = true;
    }
    for (auto it = stop_ends_.begin(); it != stop_ends_.end();) {
      if (!due(it->sim_s)) {
        ++it;
        continue;
      }
      const absl::Status resumed = it->zone.empty()
                                       ? Ctl({"resume", "--all"})
                                       : Ctl({"resume", "--zone", it->zone, "--map", s_.map_id});
      if (!resumed.ok()) {
        stop_failures_.push_back(
            absl::StrCat("the resume at ", it->sim_s, " s failed: ", resumed.message()));
      }
      it = stop_ends_.erase(it);
      changed = true;
    }
    for (size_t i = 0; i < s_.faults.size(); ++i) {
      if (!injected_[i] && due(s_.faults[i].at_s)) {
        injected_[i] = true;
        Inject(s_.faults[i]);
        changed = true;
      }
    }
    if (changed) {
      if (absl::Status settled = Settle(120.0); !settled.ok()) return settled;
    }
    const bool server_up = ServerUp();
    if (failover_) {
      const std::optional<std::pair<size_t, int64_t>> leader = Leader();
      if (leader && leader->second > failover_->epoch) {
        failovers_s_.push_back(SecondsSince(failover_->killed));
        failover_.reset();
      }
    }
    if (server_up) {
      for (size_t i = 0; i < s_.jobs.size(); ++i) {
        if (!submitted_[i] && due(s_.jobs[i].at_s)) Submit(i);
      }
      Poll(sim_s);
    }
    DrawProgress(sim_s);
    const bool all_ended =
        std::all_of(jobs_.begin(), jobs_.end(), [](const JobOutcome& j) { return IsEnd(j.state); });
    if (all_ended || sim_s >= s_.expect.deadline_s) break;
    // The next hold: the next poll, or an earlier event.
    double next_s = sim_s + kPollPeriodS;
    const auto earlier = [&](double at_s) {
      if (!due(at_s)) next_s = std::min(next_s, at_s);
    };
    earlier(s_.expect.deadline_s);
    for (const Restart& restart : restarts_) earlier(restart.due_sim_s);
    for (const LinkRestore& restore : link_restores_) earlier(restore.sim_s);
    for (const StopEnd& end : stop_ends_) earlier(end.sim_s);
    for (size_t i = 0; i < s_.faults.size(); ++i) {
      if (!injected_[i]) earlier(s_.faults[i].at_s);
    }
    for (size_t i = 0; i < s_.jobs.size(); ++i) {
      if (!submitted_[i]) earlier(s_.jobs[i].at_s);
    }
    const std::optional<double> reached = RunUntil(next_s);
    if (!reached) break;  // the simulator is gone
    sim_s = *reached;
  }
  return sim_s;
}

void Run::Submit(size_t index) {
  const ScenarioJob& job = s_.jobs[index];
  v1::SubmitJobRequest request;
  if (job.goal) {
    request.mutable_goal()->set_map_id(s_.map_id);
    *request.mutable_goal()->mutable_goal() = fleetnav::ToProto(*job.goal);
  } else {
    request.set_route_name(job.route);
  }
  request.set_robot_id(job.robot_id);
  request.set_priority(job.priority);
  // Submitting again after a server restart names the same job.
  request.set_idempotency_key(absl::StrCat("scenario/", s_.name, "/", job.name));
  grpc::ClientContext context;
  WithDeadline(&context);
  v1::SubmitJobResponse response;
  const grpc::Status status = fleet_->SubmitJob(&context, request, &response);
  if (!status.ok()) {
    if (status.error_code() != grpc::StatusCode::UNAVAILABLE &&
        status.error_code() != grpc::StatusCode::DEADLINE_EXCEEDED) {
      jobs_[index].state = "failed";
      jobs_[index].reason = absl::StrCat("refused by fleetnavd: ", status.error_message());
      submitted_[index] = true;
    }
    return;  // retried on the next poll while the server is away
  }
  jobs_[index].job_id = response.job().job_id();
  jobs_[index].state = StateName(response.job().state());
  submitted_[index] = true;
}

void Run::Poll(double sim_s) {
  {
    grpc::ClientContext context;
    WithDeadline(&context);
    v1::ListRobotsResponse robots;
    if (fleet_->ListRobots(&context, v1::ListRobotsRequest{}, &robots).ok()) {
      for (const v1::RobotState& robot : robots.robots()) {
        waits_[robot.robot_id()] = robot.traffic_wait();
        RobotFigures& f = figures_[robot.robot_id()];
        // fleetnavd sums, in sim time, how long each robot stood held (exact between holds).
        // A fleetnavd that started again (or a replica that took over) counts from zero: the
        // runner forgets what it saw when it kills one, and a count that fell is a new one.
        double& seen_s = held_seen_s_[robot.robot_id()];
        const double held_s = robot.traffic_held_s();
        f.waiting_s += held_s >= seen_s ? held_s - seen_s : held_s;
        seen_s = held_s;
        // Held means standing: a robot still driving the actions it was cleared for is not.
        const bool standing = robot.last_telemetry().mode() == v1::NAVIGATION_MODE_IDLE;
        if (!robot.traffic_wait().empty() && standing &&
            std::find(f.waits.begin(), f.waits.end(), robot.traffic_wait()) == f.waits.end()) {
          f.waits.push_back(robot.traffic_wait());
        }
        absl::StatusOr<Pose2> pose =
            fleetnav::FromProto(robot.last_telemetry().pose_in_map().pose());
        if (pose.ok()) estimates_[robot.robot_id()] = *pose;
      }
    }
  }
  // One listing of the unfinished jobs per hold: a GetJob per job would be most of the run's
  // messages with dozens of jobs. A job no longer listed has ended and is read once more.
  std::map<std::string, v1::Job> unfinished;
  if (!ListUnfinishedJobs(&unfinished)) return;  // the server did not answer: the next hold
  for (size_t i = 0; i < jobs_.size(); ++i) {
    if (!submitted_[i] || jobs_[i].job_id.empty() || IsEnd(jobs_[i].state)) continue;
    v1::Job job;
    if (auto listed = unfinished.find(jobs_[i].job_id); listed != unfinished.end()) {
      job = std::move(listed->second);
    } else {
      grpc::ClientContext context;
      WithDeadline(&context);
      v1::GetJobRequest request;
      request.set_job_id(jobs_[i].job_id);
      v1::GetJobResponse response;
      if (!fleet_->GetJob(&context, request, &response).ok()) continue;
      job = std::move(*response.mutable_job());
    }
    const std::string state = StateName(job.state());
    jobs_[i].robot_id = job.assigned_robot_id();
    jobs_[i].reason = job.reason();
    if (state != jobs_[i].state && opt_.progress != nullptr && !opt_.progress_is_terminal) {
      *opt_.progress << absl::StrFormat("t=%7.1f s  %-16s %-8s %s%s\n", sim_s, jobs_[i].name,
                                        jobs_[i].robot_id, state,
                                        jobs_[i].reason.empty() ? "" : ": " + jobs_[i].reason);
    }
    jobs_[i].state = state;
    progress_[i] = job.progress_fraction();
    if (IsEnd(state)) jobs_[i].end_sim_s = EndSimS(job, sim_s);
  }
}

double Run::EndSimS(const v1::Job& job, double held_at_s) const {
  // fleetnavd stamps on the simulation's calendar: the record says at which tick it ended.
  if (job.updated_unix_ms() < sim_start_unix_ms_) return held_at_s;
  return std::min(held_at_s,
                  static_cast<double>(job.updated_unix_ms() - sim_start_unix_ms_) * 1e-3);
}

bool Run::ListUnfinishedJobs(std::map<std::string, v1::Job>* jobs) {
  v1::ListJobsRequest request;
  for (const v1::JobState state : {v1::JOB_STATE_QUEUED, v1::JOB_STATE_ASSIGNED,
                                   v1::JOB_STATE_RUNNING, v1::JOB_STATE_PAUSED}) {
    request.add_states(state);
  }
  request.set_page_size(1000);
  do {
    grpc::ClientContext context;
    WithDeadline(&context);
    v1::ListJobsResponse response;
    if (!fleet_->ListJobs(&context, request, &response).ok()) return false;
    for (v1::Job& job : *response.mutable_jobs()) {
      const std::string id = job.job_id();
      (*jobs)[id] = std::move(job);
    }
    request.set_page_token(response.next_page_token());
  } while (!request.page_token().empty());
  return true;
}

std::optional<double> Run::RunUntil(double sim_s) {
  grpc::ClientContext context;
  // No deadline of its own: a slow machine makes the run slower, never different.
  WithDeadline(&context, std::max(1.0, opt_.wall_timeout_s));
  v1::RunUntilRequest request;
  request.set_sim_time_ns(std::llround(sim_s * 1e9));
  v1::RunResponse response;
  if (!simulator_->RunUntil(&context, request, &response).ok()) return std::nullopt;
  return static_cast<double>(response.sim_time_ns()) * 1e-9;
}

absl::Status Run::Settle(double wall_timeout_s) {
  const Clock::time_point give_up =
      Clock::now() + std::chrono::milliseconds(static_cast<int64_t>(wall_timeout_s * 1000));
  const bool server_up = ServerUp();
  std::string missing;
  while (Clock::now() < give_up) {
    missing.clear();
    std::set<std::string> attached;
    {
      grpc::ClientContext context;
      WithDeadline(&context);
      v1::GetWorldResponse world;
      if (simulator_->GetWorld(&context, v1::GetWorldRequest{}, &world).ok()) {
        for (const v1::SimRobotInfo& robot : world.robots()) {
          if (robot.attached()) attached.insert(robot.robot_id());
        }
      }
    }
    std::set<std::string> online;
    if (server_up) {
      grpc::ClientContext context;
      WithDeadline(&context);
      v1::ListRobotsResponse robots;
      if (fleet_->ListRobots(&context, v1::ListRobotsRequest{}, &robots).ok()) {
        for (const v1::RobotState& r : robots.robots()) {
          if (r.connection() == v1::CONNECTION_STATE_ONLINE) online.insert(r.robot_id());
        }
      } else {
        missing = "fleetnavd's robots";
      }
    }
    for (const auto& [id, agent] : agents_) {
      const bool running = agent != nullptr && agent->running();
      const auto link = links_.find(id);
      const bool linked = running && (link == links_.end() || !link->second->cut());
      if (running && !attached.contains(id)) absl::StrAppend(&missing, " ", id, " attached");
      if (server_up && linked != online.contains(id)) {
        absl::StrAppend(&missing, " ", id, linked ? " online" : " offline");
      }
    }
    if (missing.empty()) return absl::OkStatus();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return absl::DeadlineExceededError(
      absl::StrCat("the simulator and fleetnavd did not settle within ", wall_timeout_s,
                   " s: waiting for", missing));
}

void Run::DrawProgress(double sim_s) {
  if (opt_.progress == nullptr || !opt_.progress_is_terminal) return;
  std::ostream& out = *opt_.progress;
  if (drawn_lines_ > 0) out << "\033[" << drawn_lines_ << "A";
  drawn_lines_ = 0;
  out << absl::StrFormat("\033[2K%s  sim %.1f s\n", s_.name, sim_s);
  ++drawn_lines_;
  for (size_t i = 0; i < jobs_.size(); ++i) {
    const int filled = static_cast<int>(std::lround(std::clamp(progress_[i], 0.0, 1.0) * 30));
    const std::string bar = std::string(filled, '#') + std::string(30 - filled, '.');
    const std::string wait = waits_[jobs_[i].robot_id];
    out << absl::StrFormat("\033[2K%-16s %-8s [%s] %3d%%  %-10s %s\n", jobs_[i].name,
                           jobs_[i].robot_id, bar, static_cast<int>(progress_[i] * 100),
                           submitted_[i] ? jobs_[i].state : "waiting",
                           IsEnd(jobs_[i].state) ? jobs_[i].reason : wait);
    ++drawn_lines_;
  }
  out.flush();
}

}  // namespace fleetnav::scenario::internal
