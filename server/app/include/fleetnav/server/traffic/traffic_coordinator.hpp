#pragma once

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "absl/status/status.h"
#include "absl/synchronization/mutex.h"
#include "fleetnav/core/clock.hpp"
#include "fleetnav/core/robot_stop.hpp"
#include "fleetnav/planner/coordination/capacity_zones.hpp"
#include "fleetnav/planner/coordination/detour.hpp"
#include "fleetnav/planner/coordination/make_way.hpp"
#include "fleetnav/planner/coordination/route_prediction.hpp"
#include "fleetnav/planner/coordination/traffic_schedule.hpp"
#include "fleetnav/planner/grid/costmap.hpp"
#include "fleetnav/planner/single_robot/single_robot_planner.hpp"
#include "fleetnav/server/robots/fleet_registry.hpp"
#include "fleetnav/server/robots/robot_mailbox.hpp"
#include "fleetnav/server/site/site_cache.hpp"
#include "fleetnav/server/site/zone_catalog.hpp"
#include "fleetnav/server/traffic/planning_thread.hpp"

namespace fleetnav::server {

struct TrafficCoordinatorParams {
  /// Grown around each swept footprint of a robot that does not follow its predicted path
  /// closely (the Lely's estimate is within 0.5 m at p95; an Ackermann robot's pure pursuit
  /// cuts corners), and the most any robot's swept or standing region is grown.
  double margin_m = 0.5;
  /// A robot that follows its path closely (laser-localized against the map, not Ackermann)
  /// sweeps its footprint grown by where it stands (its standing margin below, from its
  /// covariance) plus this allowance for its path tracker's error, at most margin_m: two
  /// platforms pass each other in an aisle while a drifting Lely keeps a wide berth.
  double tracking_allowance_m = 0.1;
  /// A robot standing still is off its estimate by its localization error alone: where it
  /// stands (before, between and after its actions, and without a job) is grown by
  /// standing_sigmas standard deviations of its position (its telemetry's covariance, the
  /// larger of x and y), at least standing_margin_min_m and at most margin_m. So a
  /// laser-localized platform parked beside another is not in the other's way, while a
  /// drifting Lely keeps a wide berth.
  double standing_margin_min_m = 0.2;
  double standing_sigmas = 3.0;
  double cell_m = 0.2;
  /// Free-navigation legs are ordered in segments of about this much travel (0: whole
  /// actions), for agents that stand before a segment's gate
  /// (RobotIdentity::segment_clearances), localize with a laser against the map and steer
  /// other than by Ackermann; so robots follow one another through a shared place a segment
  /// apart. Route actions that follow the site (fence, stripe, straight, dock), robots that
  /// localize otherwise (the Lely's estimate drifts by up to half a metre between markers: a
  /// segment behind another is within its drift), Ackermann robots (one stood at a gate 6 cm
  /// from a platform passing in the store fleet) and older agents get whole actions.
  double segment_m = 1.5;
  /// Actions predicted and ordered ahead of a robot's first unfinished one. The next window is
  /// predicted, from where the robot then is, once it is within half a window of the end, so
  /// the work per dispatcher pass does not grow with the length of routes.
  int horizon_actions = 32;
  /// Clearances are decided again at once when a job begins, ends, finishes an action or its
  /// robot reconnects; otherwise at most this often (clock time), for robots without a job
  /// that moved and robots that reported where they are.
  double recheck_period_s = 0.5;
  planner::RoutePredictionParams prediction;
  /// Where a robot without a job that stands in a waiting robot's way is sent.
  planner::MakeWayParams make_way;
  /// When the robots' waits close a circle (planner::FindWaitCycles), the robot in it whose
  /// job has not started and was expected to start last is sent aside and its job given again
  /// (a make-way job is given up for a place off today's ways); each robot at most this often
  /// (clock time), so a circle that forms again is broken again without churning.
  double break_cycle_every_s = 20.0;
  /// A robot whose next free-navigation step waits for a robot that stands in its way (parked,
  /// or held) is planned a way round the robots that stand (planner::PlanDetour) and drives it
  /// (agents that said RobotIdentity::planned_paths); each robot at most this often (clock
  /// time). 0: never.
  double detour_every_s = 10.0;
  /// A robot stepping aside (StepAsideUnderWay) is expected to stand at the place aside this
  /// long before it drives on, so that the robots whose ways cross the rest of its way are
  /// ordered before it (they are what it stepped aside for).
  double step_aside_dwell_s = 30.0;
  planner::DetourParams detour;
  absl::Status Validate() const;
};

/// A robot without a job stands in a waiting robot's way: it is to drive to `place` (map
/// frame), off every way the jobs on its map still need and off where other idle robots stand.
struct MakeWayRequest {
  std::string robot_id;
  std::string map_id;
  Pose2 place;
  std::string for_robot_id;  ///< a robot that waits for it
  /// Its job, when it has one that traffic coordination holds and that it has not started:
  /// the job is to be withdrawn (queued again) before the robot goes.
  std::string withdraw_job_id;
  /// The robots' waits close a circle through this robot: a make-way job it holds is given up
  /// (cancelled) for this place, where otherwise a make-way job is never withdrawn.
  bool breaks_wait_cycle = false;
};

/// A change of why a robot's job is held, for the job's events.
struct TrafficWaitChange {
  std::string robot_id;
  std::string job_id;
  std::string reason;  ///< empty: no longer held
};

/// Executes traffic coordination for every job a robot runs (issue: fleet in the loop). When a
/// job starts, the route is predicted from the robot's pose (planner::PredictRoute; free
/// navigation planned as the agent plans it) and each action's swept footprint, grown by
/// margin_m, becomes a cell set; Update() orders the actions of all jobs that share floor with
/// planner::DecideClearances and sends each robot a TrafficClearance whenever the last action it
/// may enter grows. Robots without a job that are online stand where they are and are never
/// driven through; one that stands in a waiting robot's way is asked, once until it has a job
/// again, to make way (TakeMakeWayRequests: a place found by planner::FindMakeWayPlace; when
/// there is none, the waiting robot's reason says so). So is a robot whose job is held whole
/// (the routes cannot be ordered, e.g. two robots swapping places) before it has started it:
/// its job is to be withdrawn and given again once it has made way. A robot whose job is
/// paused keeps its region. Thread-safe (one mutex; it calls the registry and the mailbox, which
/// never block).
class TrafficCoordinator {
 public:
  TrafficCoordinator(SiteCache* site_data, FleetRegistry* registry, RobotMailbox* mailbox,
                     const Clock* clock, TrafficCoordinatorParams params);

  /// The zones whose no-go areas the predictions and ways round plan around, as the agents do
  /// (docs/server.md, "Zones"). Set before the coordinator is shared; without it they plan on
  /// the map alone.
  void UseZones(ZoneCatalog* zones) { zones_ = zones; }
  /// The operators' stops in force (StopControl's), given whenever they change: a robot outside
  /// a stopped zone whose free-navigation action crosses it is planned a way round it (docs/
  /// server.md, "Stops").
  void SetStops(std::vector<RobotStop> stops);
  /// A map's zones changed (ZoneCatalog's listener): robots whose ways cross a no-go zone new to
  /// their job are looked at on the next Update, not at its next recheck.
  void ZonesChanged();

  /// Begin's resume_action for a job resumed after a server restart: the robot is in the
  /// action its telemetry reports. Until its robot has reported, no other robot on the job's
  /// map is cleared further (it may stand in their way).
  static constexpr int kResumeWhereReported = -2;
  /// Starts coordinating a job the robot was given (resume_action -1), or one it is already
  /// running in action `resume_action` (or kResumeWhereReported).
  void Begin(const std::string& robot_id, const JobAssignment& assignment, int resume_action = -1);
  /// Whether the job is coordinated.
  bool Tracks(const std::string& job_id);
  /// The robot finished `action_index` of `job_id`.
  void OnActionFinished(const std::string& robot_id, const std::string& job_id, int action_index);
  /// The job ended (succeeded, failed, cancelled or taken away): its robot stands where it is.
  void End(const std::string& job_id);
  /// The robot opened a new stream: its clearance is sent again on the next Update.
  void Resend(const std::string& robot_id);
  /// Predicts routes that wait for a pose, decides clearances, sends those that changed, and
  /// returns the robots whose wait reason changed. Returns at once when nothing changed since
  /// the last decision and recheck_period_s has not passed.
  std::vector<TrafficWaitChange> Update();
  /// The robots without a job that Update found standing in a waiting robot's way since the
  /// last call, each with the place it is to go to. A robot is asked once until it is given a
  /// job (JobMatcher submits the make-way job); one that had no place looks again once some
  /// job has ended.
  std::vector<MakeWayRequest> TakeMakeWayRequests();

  /// Runs the searches (route predictions, ways round robots that stand) on a thread of their
  /// own from now on (PlanningThread); `on_searched` is called on it after each one (fleetnavd
  /// wakes its dispatcher). Without it they run within Update on the caller's thread.
  void StartSearchThread(std::function<void()> on_searched);
  /// Ends the search thread (searches not begun are dropped); later ones run within Update.
  void StopSearchThread();
  /// Whether a search an Update gave has not yet been taken up by an Update.
  bool SearchesPending();
  /// Blocks until every search given so far has finished: in a simulated run's lockstep each
  /// pass waits for them first, so that a search is taken up by the same pass in every run.
  void WaitForSearches();
  /// CPU time of each search on the search thread. Read after StopSearchThread.
  PassFigures search_cpu() const { return searches_.task_cpu(); }

 private:
  /// One unit traffic coordination orders: a segment of an action.
  struct Step {
    int action = 0;
    int segment = 0;
    int segments = 1;           ///< of the action
    std::optional<Pose2> gate;  ///< where it ends, unless it is the action's last
  };
  struct PendingPrediction;
  struct Tracked {
    std::string robot_id;
    JobAssignment assignment;
    RobotModel model;
    double assigned_s = 0.0;  ///< when the current window was predicted
    int start_action = 0;     ///< actions before it had run before coordination began
    bool resume_from_telemetry = false;
    bool segment_clearances = false;  ///< its agent stands before a segment's gate
    /// The schedule orders steps (its "actions" are these), of actions before predicted_end.
    std::optional<planner::ScheduledRoute> schedule;
    std::vector<Step> steps;  ///< in the order of their actions
    int predicted_end = 0;    ///< actions before it are in the schedule
    int sent_cleared = -2;    ///< the clearance last sent; -2: none
    std::string reason;
    bool planned_paths = false;  ///< its agent drives a planned path (RobotIdentity)
    /// Paths planned round robots that stand, by action; sent with the clearances.
    std::map<int, ActionPath> paths;
    /// Places on those paths where the robot stands until it is cleared on (a segment ends
    /// there): where it steps aside (StepAsideUnderWay).
    std::map<int, std::vector<Eigen::Vector2d>> stops;
    double detour_tried_s = -1e300;  ///< when a detour was last looked for
    /// Set when the way of the action the robot is in was planned again: where it stood, which
    /// is where it stands until the new way is cleared.
    std::optional<SegmentHold> hold_under_way;
    /// Its window is to be predicted (again): its job began, or it came near the window's end.
    /// Until the prediction is taken up, the schedule it has (if any) stays in force.
    bool needs_prediction = true;
    /// Grows with every change that makes a search under way for it stale (an action
    /// finished, a window ended, a prediction or a way round taken up).
    uint64_t revision = 0;
    std::shared_ptr<PendingPrediction> prediction;  ///< given, not yet taken up
    /// Its lane of each one-at-a-time zone its schedule has entered, by zone name
    /// (planner::CapacityZones), kept for the job so that a new window keeps the lane.
    std::map<std::string, int> zone_lanes;
  };
  /// What a window's prediction is made from: copies, so that it runs on the search thread.
  struct PredictionInput {
    std::string robot_id;
    std::string job_id;
    std::string map_id;
    uint32_t map_version = 0;
    std::shared_ptr<const Route> route;
    RobotModel model;
    int start_action = 0;
    double assigned_s = 0.0;
    bool segment_clearances = false;
    bool resume_from_telemetry = false;
    std::map<int, ActionPath> paths;
    std::map<int, std::vector<Eigen::Vector2d>> stops;
    std::optional<SegmentHold> hold_under_way;
    Pose2 pose;
    std::optional<Eigen::Vector2d> carried_load_m;
    double standing_margin_m = 0.0;
    double swept_margin_m = 0.0;
    std::shared_ptr<const storage::StoredMarkerSet> markers;
  };
  /// A predicted window: its schedule (cells_id not yet set) and steps.
  struct Prediction {
    planner::ScheduledRoute schedule;
    std::vector<Step> steps;
    int predicted_end = 0;
    /// Whether the robot's planner found its ways (else straight lines stand in for them).
    bool planned = true;
  };
  /// A search on the thread is taken up by a later Update than the one that gave it, never by
  /// the same (it would be taken up there or not by how fast it ran: runs would differ); one
  /// run at once (no thread) is taken up at once.
  struct Given {
    uint64_t ticket = 0;
    uint64_t update = 0;  ///< the Update that gave it
    bool ran_at_once = false;
  };
  struct PendingPrediction {
    Given given;
    uint64_t revision = 0;  ///< the job's when it was given
    Prediction result;      ///< written by the search
  };
  /// A way round robots that stand, searched for one robot, with its window predicted along it.
  struct PendingDetour {
    Given given;
    std::string job_id;
    uint64_t revision = 0;
    int action = 0;
    Pose2 from;  ///< where the robot stood
    double assigned_s = 0.0;
    std::vector<Eigen::Vector2d> stops;  ///< places on the way where it stands (Tracked::stops)
    bool found = false;                  ///< written by the search, with what follows
    ActionPath path;
    std::optional<SegmentHold> hold_under_way;
    Prediction prediction;
  };
  struct PlannerCache {
    std::unique_ptr<planner::Costmap> costmap;
    std::unique_ptr<planner::SingleRobotPlanner> planner;
    Pose2 map_origin;
  };

  /// What predicting `tracked`'s window from where its robot stands by `telemetry` needs.
  PredictionInput PredictionInputOf(const Tracked& tracked, const Telemetry& telemetry) const;
  /// Gives the search thread the prediction of `tracked`'s window from `telemetry`.
  void GivePrediction(Tracked& tracked, const Telemetry& telemetry)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// Takes up a finished prediction: its schedule replaces the one in force.
  void TakePrediction(Tracked& tracked, Prediction prediction)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// Schedules the window of actions ahead from the input's pose, the robot carrying its load
  /// as it starts. Runs on the search thread: it reads only its input, params_ and `cache`.
  Prediction PredictWindow(const PredictionInput& input, PlannerCache& cache) const;
  /// Gives the search thread `search`.
  Given GiveSearch(std::function<void()> search) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// Whether a search given may be taken up now.
  bool Finished(const Given& given) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// Gives the search thread a new way for `t`'s action `action` (`nav`) from where its robot
  /// stands by `telemetry`: `way` finds the waypoints, and the window is predicted along them;
  /// TakeDetour keeps both when the robot's planner could follow them (at once, without the
  /// search thread). `stops`: places on the way where it stands until cleared on.
  void GiveWayRound(Tracked& t, int action, const FreeNavigationAction& nav,
                    const Telemetry& telemetry, std::vector<Eigen::Vector2d> stops,
                    std::function<absl::StatusOr<std::vector<Eigen::Vector2d>>()> way,
                    const std::map<std::string, const RobotRecord*>& records)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// Takes up the detour searched for, when its job has not moved on since.
  void TakeDetour(const std::map<std::string, const RobotRecord*>& records)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// Where `robot` stands by its last telemetry (which it must have): its footprint, carrying
  /// its load, grown by its standing margin plus `more_m`.
  planner::CellSet WhereItStands(const RobotRecord& robot, double more_m = 0.0) const;
  /// How far to grow what a robot of `model` with this telemetry sweeps while it drives:
  /// margin_m, or for one that follows its path closely its standing margin plus
  /// tracking_allowance_m (at most margin_m).
  double SweptMarginM(const RobotModel& model, const Telemetry& telemetry) const;
  /// How far to grow where a robot with this telemetry stands (standing_margin_min_m..margin_m).
  double StandingMarginM(const Telemetry& telemetry) const;
  PlannerCache& CacheFor(const std::string& map_id, uint32_t map_version, const RobotModel& model)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// The same kept for the searches alone (they run on the search thread; a costmap fills its
  /// cache as it is used).
  PlannerCache& SearchCacheFor(const std::string& map_id, uint32_t map_version,
                               const RobotModel& model);
  /// A costmap and the agent's planner of `model`'s kind for the map version, on the map with
  /// the no-go zones of `zones` (may be null) occupied.
  PlannerCache BuildPlannerCache(const std::string& map_id, uint32_t map_version,
                                 const RobotModel& model, const ZoneSet* zones) const;
  /// The one-at-a-time zones of the map's latest zone set (nullptr when it has none), on the
  /// coordinator's cells; built once per zone version.
  std::shared_ptr<const planner::CapacityZones> CapacityZonesOf(const std::string& map_id)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// Adds to `tracked`'s schedule the lanes of the one-at-a-time zones it enters
  /// (planner::CapacityZones::Apply): a zone it has no lane of yet is given the lane the
  /// fewest other jobs of its map still to drive through the zone hold.
  void KeepCapacityZones(Tracked& tracked) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// `parked` with the lane cells added to each robot that stands in a one-at-a-time zone of
  /// `map_id` (the lane of its last job there, else the first), in `storage`; `parked` itself
  /// when the map has no such zone.
  const std::vector<planner::ParkedRobot>& ParkedWithCapacityZones(
      const std::string& map_id, const std::vector<planner::ParkedRobot>& parked,
      std::vector<planner::ParkedRobot>& storage) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// The map's latest zones when it has a no-go zone; nullptr else.
  std::shared_ptr<const storage::StoredZoneSet> NoGoZonesOf(const std::string& map_id) const;
  /// Costmaps and planners by (map id, map version, robot kind, zone version), built on first
  /// use.
  using PlannerCaches =
      std::map<std::tuple<std::string, uint32_t, std::string, uint32_t>, PlannerCache>;
  /// `caches`' entry for the map version and `model`'s kind, built when it has none.
  PlannerCache& CacheIn(PlannerCaches& caches, const std::string& map_id, uint32_t map_version,
                        const RobotModel& model) const;
  /// Finds a place for each idle robot that a decision on `map_id` waits for (not asked yet)
  /// and queues the request, or notes why there is none.
  void AskIdleRobotsToMakeWay(const std::string& map_id, const std::vector<Tracked*>& tracked_jobs,
                              const std::vector<planner::TrafficClearanceDecision>& decisions,
                              const std::vector<planner::ParkedRobot>& parked,
                              const std::map<std::string, const RobotRecord*>& records)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// Where `robot` could stand off every way the jobs on `map_id` still need (its own job's
  /// left out) and off the other idle robots; NotFound naming the place when there is none.
  /// With `near_only_except`, the routes of robots not in it are kept off only as far as they
  /// are cleared and one step more, and where they end (a fleet's whole ways can cover a dense
  /// hall; a robot that later stands in someone's way is asked to make way again). The way
  /// there does not pass where another robot of the map stands (`records`), when there is
  /// such a place.
  absl::StatusOr<Pose2> PlaceAside(const std::string& map_id, uint32_t map_version,
                                   const RobotRecord& robot,
                                   const std::vector<Tracked*>& tracked_jobs,
                                   const std::vector<planner::ParkedRobot>& parked,
                                   const std::map<std::string, const RobotRecord*>& records,
                                   const std::vector<std::string>* near_only_except = nullptr)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// For each circle of waits among the decisions (planner::FindWaitCycles), sends aside a
  /// robot in it whose job has not started, withdrawing that job: the one sent aside for a
  /// circle least often, then one that stands in another's way, then the one expected to start
  /// last; a circle one of whose robots was sent aside within break_cycle_every_s is left alone.
  void BreakWaitCycles(const std::string& map_id, const std::vector<Tracked*>& tracked_jobs,
                       const std::vector<planner::TrafficClearanceDecision>& decisions,
                       const std::vector<planner::ParkedRobot>& parked,
                       const std::map<std::string, const RobotRecord*>& records)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// Sends `t`'s robot, under way and standing at its gate on a free-navigation action without
  /// waypoints of its own, aside within that action: its way goes through a place off every
  /// other robot's way (PlaceAside) to the action's goal, and it stands where it is until that
  /// way is cleared. Returns whether it was sent.
  bool StepAsideUnderWay(const std::string& map_id, Tracked& t,
                         const planner::TrafficClearanceDecision& d,
                         const std::vector<Tracked*>& tracked_jobs,
                         const std::vector<planner::ParkedRobot>& parked,
                         const std::map<std::string, const RobotRecord*>& records)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// Holds back what the decisions newly clear where it meets another robot of the map where
  /// that robot stands now by its telemetry (footprint grown by its standing margin): the
  /// orders are computed on predicted places, and a robot off its prediction (a way it planned
  /// again, its tracker's error) is then waited for as one that stands in the way.
  void HoldClearOfWhereRobotsAre(const std::vector<Tracked*>& tracked_jobs,
                                 std::vector<planner::TrafficClearanceDecision>& decisions,
                                 const std::map<std::string, const RobotRecord*>& records)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// For each robot on `map_id` whose next free-navigation step waits for a robot that stands
  /// in its way: a way round the robots that stand (parked, held, or not cleared further),
  /// which its window is then predicted along (its schedule starts again from that action).
  void PlanDetours(const std::string& map_id, const std::vector<Tracked*>& tracked_jobs,
                   const std::vector<planner::TrafficClearanceDecision>& decisions,
                   const std::map<std::string, const RobotRecord*>& records)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// Gives the search thread PlanDetours' search for one robot: `t`'s action `action` (`nav`)
  /// from where `robot` stands, round the robots that stand on `map`, and its window predicted
  /// along the way found (TakeDetour keeps them).
  void PlanWayRound(Tracked& t, int action, const FreeNavigationAction& nav,
                    const RobotRecord& robot, std::shared_ptr<const storage::StoredMap> map,
                    const std::vector<Tracked*>& tracked_jobs,
                    const std::vector<planner::TrafficClearanceDecision>& decisions,
                    const std::map<std::string, const RobotRecord*>& records)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// For a robot on `map_id` outside every closed zone whose free-navigation action in hand
  /// crosses one: a way round the closed zones (grown so that its reach keeps off them), through
  /// its own waypoints still ahead and off the zones, which its window is then predicted along.
  /// Closed: the stopped zones, and for a job given before the map's latest zones their no-go
  /// zones (its agent planned the action in hand without them, and brakes short of them). At
  /// most one search at a time, each robot at most every detour_every_s.
  void PlanWaysRoundStops(const std::string& map_id, const std::vector<Tracked*>& tracked_jobs,
                          const std::map<std::string, const RobotRecord*>& records)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// The indices of `latest`'s no-go zones that the zone version a job was given
  /// (`given_version`, 0: none) did not have with that name and outline.
  std::vector<size_t> NoGoZonesNewTo(const storage::StoredZoneSet& latest, uint32_t given_version)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// The waypoints of `nav` a robot at `at` has still to pass: those from the leg it is nearest
  /// to on (the polyline through them to the goal).
  static std::vector<Eigen::Vector2d> WaypointsAhead(const FreeNavigationAction& nav,
                                                     const Eigen::Vector2d& at);
  /// Why the decision holds the robot, for people ("" when it does not); `jobs_on_map` are
  /// the tracked jobs the decision's waits may name, by robot id.
  static std::string Describe(const planner::TrafficClearanceDecision& d,
                              const std::map<std::string, const Tracked*>& jobs_on_map);
  /// The decision as the robot's agent is told it: actions (and a gate within the last one).
  static ClearanceNotice Notice(const Tracked& tracked, const planner::TrafficClearanceDecision& d,
                                const std::map<std::string, const Tracked*>& jobs_on_map,
                                const std::string& reason);
  /// Moves the job past the gates its robot's telemetry shows it has reached.
  static void PassGates(Tracked& tracked, const Telemetry& telemetry);
  /// The first step of `action` (steps.size() past the last predicted action).
  static int FirstStepOf(const Tracked& tracked, int action);
  static int FirstStepOf(const std::vector<Step>& steps, int action);
  /// The action of `step` (a step index outside the schedule is returned as it is: -1 none).
  static int ActionOfStep(const Tracked& tracked, int step);

  SiteCache* site_data_;
  ZoneCatalog* zones_ = nullptr;
  FleetRegistry* registry_;
  RobotMailbox* mailbox_;
  const Clock* clock_;
  TrafficCoordinatorParams params_;
  absl::Mutex mutex_;
  std::map<std::string, Tracked> jobs_ ABSL_GUARDED_BY(mutex_);
  /// Where each robot without a coordinated job stood when last swept, what it carried, and
  /// the cells.
  struct ParkedSweep {
    Pose2 pose;
    std::optional<Eigen::Vector2d> carried_load_m;
    double margin_m = 0.0;
    planner::CellSet cells;
  };
  std::map<std::string, ParkedSweep> parked_cells_ ABSL_GUARDED_BY(mutex_);  ///< by job id
  /// Costmap and planner per (map id, map version, robot kind).
  PlannerCaches planners_ ABSL_GUARDED_BY(mutex_);
  /// The searches' own (SearchCacheFor): touched by one search at a time, on the search thread
  /// or within Update.
  PlannerCaches search_planners_;
  /// Remembers which pairs of predicted windows share floor, per map.
  std::map<std::string, planner::ClearanceDecider> deciders_ ABSL_GUARDED_BY(mutex_);
  uint64_t next_cells_id_ ABSL_GUARDED_BY(mutex_) = 1;
  uint64_t next_path_id_ ABSL_GUARDED_BY(mutex_) = 1;
  std::vector<MakeWayRequest> make_way_requests_ ABSL_GUARDED_BY(mutex_);
  /// Idle robots asked to make way (or found to have no place) since their last job began.
  std::set<std::string> make_way_asked_ ABSL_GUARDED_BY(mutex_);
  /// Why an idle robot in the way cannot make way, by robot id.
  std::map<std::string, std::string> cannot_make_way_ ABSL_GUARDED_BY(mutex_);
  /// A job began, ended or moved on since the last decision.
  bool changed_ ABSL_GUARDED_BY(mutex_) = true;
  double last_decision_s_ ABSL_GUARDED_BY(mutex_) = -1e300;
  uint64_t updates_ ABSL_GUARDED_BY(mutex_) = 0;  ///< Updates that decided
  /// Each robot sent aside to break a circle of waits: when it last was (clock seconds), and
  /// how often.
  struct CycleBreaks {
    double last_s = 0.0;
    int count = 0;
  };
  std::map<std::string, CycleBreaks> cycle_breaks_ ABSL_GUARDED_BY(mutex_);
  /// One-at-a-time zones per map, with the zone version they were built from.
  struct BuiltCapacityZones {
    uint32_t version = 0;
    std::shared_ptr<const planner::CapacityZones> zones;
  };
  std::map<std::string, BuiltCapacityZones> capacity_zones_ ABSL_GUARDED_BY(mutex_);
  /// The zone lanes of each robot's last job (Tracked::zone_lanes), by robot id: where it
  /// stands in such a zone after the job, it holds that lane.
  std::map<std::string, std::map<std::string, int>> last_zone_lanes_ ABSL_GUARDED_BY(mutex_);
  /// Robots whose job is still to be predicted (they stand, and are not sent aside).
  std::set<std::string> awaiting_prediction_ ABSL_GUARDED_BY(mutex_);
  /// The operators' stops in force (SetStops).
  std::vector<RobotStop> stops_ ABSL_GUARDED_BY(mutex_);
  /// Zone versions jobs were given, by (map id, version), as read (nullptr: not readable).
  std::map<std::pair<std::string, uint32_t>, std::shared_ptr<const ZoneSet>> given_zone_sets_
      ABSL_GUARDED_BY(mutex_);
  /// The detour given to the search thread and not yet taken up (one at a time).
  std::shared_ptr<PendingDetour> detour_ ABSL_GUARDED_BY(mutex_);
  /// Last, so that it ends (and its searches with it) before what they use.
  PlanningThread searches_;
};

}  // namespace fleetnav::server
