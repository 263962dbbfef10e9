#pragma once

#include <Eigen/Core>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "fleetnav/core/job.hpp"
#include "fleetnav/core/robot_state.hpp"
#include "fleetnav/server/jobs/job_ledger.hpp"
#include "fleetnav/server/jobs/job_lifecycle.hpp"
#include "fleetnav/server/jobs/job_needs.hpp"
#include "fleetnav/server/jobs/job_traffic.hpp"
#include "fleetnav/server/robots/fleet_registry.hpp"
#include "fleetnav/server/robots/robot_mailbox.hpp"
#include "fleetnav/server/site/site_cache.hpp"
#include "fleetnav/server/site/site_catalog.hpp"
#include "fleetnav/server/site/travel_distances.hpp"

namespace fleetnav::server {

struct JobMatcherParams {
  int max_page_size = 1000;
  /// A robot whose battery falls below this fraction gets no more work: it is sent to its
  /// charger and stays there until charged to charged_fraction (0: never).
  double charge_below_fraction = 0.2;
  double charged_fraction = 0.9;
  /// The route to the charger, by map id (the map of the robot's last job; the only route when
  /// there is one).
  std::map<std::string, std::string> charging_routes;
};

/// Which robot drives which queued job. Queued jobs are taken in order of priority (high first)
/// then age and go to connected, idle robots whose capabilities include every action type of
/// the route (go-to-goal jobs need "free_navigation"), the robot with the shortest path over the
/// map (TravelDistances) to the job's first known point first. A robot whose battery is low is
/// sent to its charger first and given nothing else until charged. A robot without a job that
/// stands in another's way is sent to the place traffic coordination found for it (a go-to-goal
/// job of its own). A job that stays queued says why, once per change of reason. Not thread-safe:
/// JobService serialises its callers.
class JobMatcher {
 public:
  JobMatcher(JobLedger* ledger, JobLifecycle* lifecycle, FleetRegistry* registry,
             RobotMailbox* mailbox, JobTraffic* traffic, SiteCatalog* site, SiteCache* site_data,
             JobMatcherParams params)
      : ledger_(ledger),
        lifecycle_(lifecycle),
        registry_(registry),
        mailbox_(mailbox),
        traffic_(traffic),
        site_(site),
        site_data_(site_data),
        params_(std::move(params)),
        travel_(site_data) {}

  /// Submits a charging job for each idle robot whose battery is low and that is not charging.
  void SendLowRobotsToCharge();
  /// Submits a go-to-goal job to its place for each robot asked to make way that has no
  /// make-way job pending (highest priority, so the next pass gives it before anything else),
  /// unless the robot's last job was on another map.
  void SendToMakeWay(const std::vector<MakeWayRequest>& requests);
  /// Whether SendToMakeWay would send the robot of `request` (its make-way job `ending_job_id`,
  /// if any, counted as ended): a job is withdrawn only for a robot that then goes aside, or
  /// it is given again at once, held and withdrawn again, ten times a second.
  bool WouldSendToMakeWay(const MakeWayRequest& request, const std::string& ending_job_id) const;
  /// Whether `job_id` is a make-way job this matcher submitted (never withdrawn: withdrawing
  /// what moves a robot out of the way would only queue the same move again).
  bool IsMakeWayJob(const std::string& job_id) const;
  /// Assigns what can be assigned now; returns jobs assigned.
  int AssignQueued();
  /// A job of the robot succeeded: if it was not its make-way job, a make-way job that failed
  /// before no longer keeps the robot from being sent to make way.
  void OnJobSucceeded(const std::string& robot_id, const std::string& job_id);
  /// Forgets what is kept about a robot that is removed.
  void ForgetRobot(const std::string& robot_id);

 private:
  /// What matching needs to know of a job's route: the action types it needs and its first
  /// known point.
  struct RouteFacts {
    /// The capabilities the job needs, sorted (what robots are matched on).
    std::vector<std::string> needed;
    std::vector<NeededCapability> needs;  ///< the same, in the route's order, with the action
    std::optional<Eigen::Vector2d> start;
    static RouteFacts Of(std::vector<NeededCapability> needs, std::optional<Eigen::Vector2d> start);
  };
  /// A route's facts are kept by (route, version), which never changes, so a queued job costs
  /// nothing per pass however long its route.
  RouteFacts FactsOf(const Job& job);
  /// What the fleet can run between its robots: those connected now, and all that ever did.
  struct FleetCapabilities {
    std::set<std::string> online;
    std::set<std::string> known;
  };
  /// Stores why `job` stays queued (one QUEUED event when the reason changes): "no robot that
  /// has connected can run actions[0] (turn)", "no connected robot can run actions[2]
  /// (stripe_navigation)", "robot lely2 is offline", "waits for robot lely2 to finish job
  /// job-000004", ….
  void SayWhyQueued(Job& job, const std::vector<NeededCapability>& needs,
                    const FleetCapabilities& fleet);
  /// Whether `robot` is kept for charging: its charging job runs, or it charges after it.
  bool HeldForCharging(const RobotRecord& robot);
  /// The idle robot nearest by path to the job's start among those that may take it.
  std::vector<RobotRecord>::iterator Nearest(std::vector<RobotRecord>& idle, const Job& job,
                                             const RouteFacts& facts);
  /// Sends `job` to `robot_id`; false (and the job re-queued) when it cannot be sent.
  bool Assign(Job& job, const std::string& robot_id);

  JobLedger* ledger_;
  JobLifecycle* lifecycle_;
  FleetRegistry* registry_;
  RobotMailbox* mailbox_;
  JobTraffic* traffic_;
  SiteCatalog* site_;
  SiteCache* site_data_;
  JobMatcherParams params_;
  TravelDistances travel_;
  std::map<std::pair<std::string, uint32_t>, RouteFacts> route_facts_;
  std::map<std::string, std::string> robot_map_;     ///< the map of each robot's last job
  std::map<std::string, std::string> charging_job_;  ///< by robot id
  std::map<std::string, std::string> make_way_job_;  ///< by robot id
};

}  // namespace fleetnav::server
