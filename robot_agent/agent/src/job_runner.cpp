#include "fleetnav/robot_agent/job_runner.hpp"

#include <algorithm>

#include "absl/strings/str_cat.h"

namespace fleetnav::agent {
namespace {

/// Kept between a stopped zone and the reach of a robot that braked before it.
constexpr double kStopSpareM = 0.05;

}  // namespace

JobRunner::JobRunner(RouteContext context, JobRunnerPorts ports, ModeParams modes,
                     SafetyParams safety, std::optional<Route> route)
    : context_(std::move(context)),
      ports_(std::move(ports)),
      modes_(modes),
      safety_(safety),
      stop_after_link_loss_s_(safety.stop_after_link_loss_s) {
  if (route) StartRoute(std::move(*route));
}

void JobRunner::StartRoute(Route route, const RoutePosition& from) {
  EndRoute();
  const Pose2 here = localizer().estimate().pose_in_map;
  executor_.emplace(std::move(route), context_, modes_, here, from);
  reported_action_ = -1;
  // Actions before the resume point were reported finished by the agent that ran them.
  finished_action_ = from.action_index - 1;
  paused_ = false;
  end_reported_ = false;
  safety_.Reset();
}

void JobRunner::EndRoute() {
  if (!executor_) return;
  // What the route has done to the site outlives it.
  context_.carried_load_m = executor_->carried_load_m();
  context_.moved_loads = executor_->moved_loads();
  executor_.reset();
}

void JobRunner::EndJob() {
  EndRoute();
  job_id_.clear();
  ports_.jobs->SetCurrentJob("");
  ++jobs_finished_;
}

void JobRunner::Report(JobEventType type, int action_index, NavigationMode mode,
                       const std::string& reason) {
  JobEvent event;
  event.job_id = job_id_;
  event.type = type;
  event.action_index = action_index;
  event.mode = mode;
  event.reason = reason;
  events_.push_back(event);
  if (ports_.jobs != nullptr && !job_id_.empty()) ports_.jobs->ReportEvent(event);
}

void JobRunner::ReportProgress(const ExecutorOutput& output) {
  // An action is reported finished once: when the next starts, or at once when the next waits
  // for traffic (the robots waiting for this one may go).
  auto finish = [&](int index) {
    if (index >= 0 && index != finished_action_) {
      Report(JobEventType::kActionFinished, index, output.mode, "");
      finished_action_ = index;
    }
  };
  if (output.waiting) {
    finish(output.action_index);
  } else if (output.action_index >= 0 && output.action_index != reported_action_) {
    finish(reported_action_);
    Report(JobEventType::kActionStarted, output.action_index, output.mode, "");
    reported_action_ = output.action_index;
  }
  if (!output.mode_reason.empty()) {
    Report(JobEventType::kModeSwitch, output.action_index, output.mode, output.mode_reason);
  }
}

ExecutorOutput JobRunner::Step(const ControlInput& input, const std::vector<int>& detected_markers,
                               const localization::LocalizerEstimate& estimate,
                               const Twist2& last_command) {
  ExecutorOutput output;
  const bool hears_server = ports_.jobs == nullptr || ports_.jobs->HearsServer();
  TakeZonesTold();
  std::vector<RobotStop> stops =
      ports_.jobs != nullptr ? ports_.jobs->Stops() : std::vector<RobotStop>{};
  if (!closed_zones_.empty() && executor_ && executor_->actions_started() != closed_since_start_) {
    closed_zones_.clear();  // the action started again on the map with them occupied
  }
  stops.insert(stops.end(), closed_zones_.begin(), closed_zones_.end());
  link_lost_s_ = hears_server ? 0.0 : link_lost_s_ + input.dt_s;
  const double reach_m = ReachM(estimate);
  if (executor_ && executor_->state() == ExecutionState::kRunning) {
    const SafetyVerdict& verdict = safety_.Check(input.perception, last_command, estimate.velocity,
                                                 estimate.lost, input.dt_s, estimate.lost_reason);
    if (verdict.stop != SafetyStop::kNone) {
      safety_stop_ = verdict.stop;
      if (verdict.stop == SafetyStop::kBumper) {
        Report(JobEventType::kBumper, executor_->action_index(), NavigationMode::kFault,
               verdict.reason);
      } else if (verdict.stop == SafetyStop::kLocalizationLost) {
        Report(JobEventType::kLocalizationLost, executor_->action_index(), NavigationMode::kFault,
               verdict.reason);
      }
      executor_->Abort(absl::AbortedError(verdict.reason));
    }
    // An operator's stop holds a robot in its zone or at its edge, its reach touching the zone
    // (one nearing the zone is slowed below). A stop made while the robot does not hear the
    // server cannot reach it: it stands.
    stopped_ =
        ApplyingStop(stops, site_map_id_, estimate.pose_in_map.translation(), reach_m) != nullptr ||
        (!hears_server && link_lost_s_ >= stop_after_link_loss_s_);
    const bool was_running = executor_->state() == ExecutionState::kRunning;
    if (was_running && !paused_ && !stopped_) {
      output = executor_->Step(input, detected_markers);
      ReportProgress(output);
    } else {
      output = executor_->Step(input, {});  // reports the state, commands nothing
    }
  } else if (executor_) {
    output = executor_->Step(input, {});
  }
  if (executor_) lift_raised_ = output.lift_raised;
  if (executor_ && executor_->state() != ExecutionState::kRunning && !end_reported_) {
    end_reported_ = true;
    if (executor_->state() == ExecutionState::kSucceeded) {
      if (output.action_index >= 0) {
        Report(JobEventType::kActionFinished, output.action_index, NavigationMode::kIdle, "");
      }
      Report(JobEventType::kSucceeded, output.action_index, NavigationMode::kIdle, "");
    } else {
      Report(JobEventType::kFailed, executor_->action_index(), NavigationMode::kFault,
             std::string(executor_->failure().message()));
    }
  }
  if (zones_) {
    if (const std::optional<double> cap = ZoneSpeedCap(
            *zones_, estimate.pose_in_map, estimate.covariance, FootprintRadiusM(), zone_speed_)) {
      output.command = CapTwist(output.command, *cap);
    }
  }
  // It brakes to stand before a stopped zone with its reach and a margin to spare (so that it
  // is not then held at the zone's edge), and drives on along or away from it.
  output.command = KeepOffStoppedZones(output.command, stops, site_map_id_, estimate.pose_in_map,
                                       reach_m + kStopSpareM, zone_speed_.braking_decel_mps2);
  if (paused_ || stopped_) {
    output.mode = NavigationMode::kPaused;
    output.command = Twist2{};
  }
  return output;
}

void JobRunner::ApplyCommand(const JobCommand& command, const ExecutorOutput& output) {
  if (command.job_id != job_id_ || job_id_.empty()) return;
  if (command.type == JobCommandType::kPause) paused_ = true;
  if (command.type == JobCommandType::kResume) paused_ = false;
  if (command.type == JobCommandType::kClearance && executor_) {
    // The action under way stays cleared whatever a new session says.
    executor_->SetClearedUpTo(std::max(command.cleared_up_to_action, executor_->action_index()));
    executor_->SetHold(command.hold);
    for (const ActionPath& path : command.paths) executor_->SetActionPath(path);
  }
  if (command.type == JobCommandType::kCancel) {
    Report(JobEventType::kCancelled, output.action_index, NavigationMode::kIdle, command.reason);
    EndJob();
  }
}

void JobRunner::Serve(const ExecutorOutput& output) {
  if (ports_.jobs == nullptr) return;
  const std::vector<JobCommand> commands = ports_.jobs->TakeCommands();
  for (const JobCommand& command : commands) {
    // Kept, for a clearance may come before the agent takes its job's assignment.
    if (command.type == JobCommandType::kClearance) clearance_ = command;
    ApplyCommand(command, output);
  }
  if (!job_id_.empty() && executor_ && executor_->state() != ExecutionState::kRunning) EndJob();
  if (!job_id_.empty()) return;
  std::optional<JobAssignment> assignment = ports_.jobs->TakeAssignment();
  if (!assignment) return;
  job_id_ = assignment->job.job_id;
  site_map_id_ = assignment->job.map_id;
  ports_.jobs->SetCurrentJob(job_id_);
  if (absl::Status site = PrepareSite(*assignment); !site.ok()) {
    // Nothing moves: the job fails at once with the reason.
    StartRoute(Route{});
    executor_->Abort(site);
    return;
  }
  StartRoute(*assignment->route, assignment->resume);
  // A job from the server waits for its traffic clearance.
  const bool cleared = clearance_.job_id == job_id_;
  executor_->SetClearedUpTo(cleared ? clearance_.cleared_up_to_action : -1);
  executor_->SetHold(cleared ? clearance_.hold : std::nullopt);
  if (cleared) {
    for (const ActionPath& path : clearance_.paths) executor_->SetActionPath(path);
  }
  // Commands about this job that came with it (a job sent again while an operator holds it
  // comes with PAUSE).
  for (const JobCommand& command : commands) {
    if (command.type != JobCommandType::kClearance) ApplyCommand(command, output);
  }
}

double JobRunner::FootprintRadiusM() const {
  const std::optional<Eigen::Vector2d> load = carried_load_m();
  return (load ? context_.model.CarryingLoad(*load) : context_.model).CircumscribedRadius();
}

void JobRunner::TakeZonesTold() {
  if (ports_.jobs == nullptr || site_map_id_.empty() || site_map_ == nullptr || !executor_ ||
      executor_->state() != ExecutionState::kRunning) {
    return;
  }
  std::optional<ToldZones> told = ports_.jobs->Zones(site_map_id_);
  if (!told || told->version == zone_version_) return;
  zone_version_ = told->version;
  std::vector<RobotStop> closed;
  for (const Zone& zone : told->zones.zones) {
    const Zone* before = zones_ ? zones_->Find(zone.name) : nullptr;
    if (zone.kind != ZoneKind::kNoGo || (before != nullptr && before->kind == ZoneKind::kNoGo &&
                                         before->polygon_in_map == zone.polygon_in_map)) {
      continue;
    }
    RobotStop stop;
    stop.map_id = site_map_id_;
    stop.zone = zone.name;
    stop.polygon_in_map = zone.polygon_in_map;
    stop.reason = "a no-go zone put while the robot drove";
    closed.push_back(std::move(stop));
  }
  closed_zones_ = std::move(closed);
  closed_since_start_ = executor_->actions_started();
  zones_.reset();
  if (!told->zones.zones.empty()) zones_ = std::move(told->zones);
  const bool has_no_go = zones_ && zones_->HasKind(ZoneKind::kNoGo);
  context_.map =
      has_no_go && site_map_ != nullptr
          ? std::make_shared<const OccupancyGrid>(WithNoGoZonesOccupied(*site_map_, *zones_))
          : site_map_;
  executor_->SetNavigationMap(context_.map);
}

double JobRunner::ReachM(const localization::LocalizerEstimate& estimate) const {
  return GrownReachM(estimate.covariance, FootprintRadiusM(), zone_speed_);
}

absl::Status JobRunner::PrepareSite(const JobAssignment& assignment) {
  const std::string& map_id = assignment.job.map_id;
  if (ports_.sites == nullptr || !ports_.make_localizer || map_id.empty()) {
    return absl::OkStatus();
  }
  const std::string key =
      absl::StrCat(map_id, "@", assignment.map_version, "/", assignment.marker_set_version, "/",
                   assignment.zone_set_version);
  if (key == site_key_) return absl::OkStatus();
  absl::StatusOr<SiteData> site =
      ports_.sites->Load(map_id, assignment.map_version, assignment.marker_set_version);
  if (!site.ok()) {
    return absl::FailedPreconditionError(
        absl::StrCat("map ", map_id, " v", assignment.map_version,
                     " could not be loaded on the robot: ", site.status().message()));
  }
  std::optional<ZoneSet> zones;
  if (assignment.zone_set_version > 0) {
    absl::StatusOr<std::optional<ZoneSet>> loaded =
        ports_.sites->LoadZones(map_id, assignment.zone_set_version);
    if (!loaded.ok()) {
      return absl::FailedPreconditionError(
          absl::StrCat("zones of map ", map_id, " v", assignment.zone_set_version,
                       " could not be loaded on the robot: ", loaded.status().message()));
    }
    zones = *std::move(loaded);
  }
  absl::StatusOr<std::unique_ptr<localization::Localizer>> made =
      ports_.make_localizer(*site, localizer().estimate().pose_in_map);
  if (!made.ok()) {
    return absl::FailedPreconditionError(
        absl::StrCat("cannot localize on map ", map_id, ": ", made.status().message()));
  }
  job_localizer_ = *std::move(made);
  // Localization keeps the true map; navigation plans on it with the no-go zones occupied.
  const bool has_no_go = zones && zones->HasKind(ZoneKind::kNoGo);
  context_.map =
      has_no_go && site->map != nullptr
          ? std::make_shared<const OccupancyGrid>(WithNoGoZonesOccupied(*site->map, *zones))
          : site->map;
  zones_ = std::move(zones);
  zone_version_ = assignment.zone_set_version;
  site_map_ = site->map;
  closed_zones_.clear();
  context_.markers = site->markers;
  context_.moved_loads = {};  // places on the map the agent worked on before
  site_key_ = key;
  return absl::OkStatus();
}

}  // namespace fleetnav::agent
