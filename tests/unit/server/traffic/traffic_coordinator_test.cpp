#include "fleetnav/server/traffic/traffic_coordinator.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <memory>
#include <vector>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/storage/memory/memory_fleet_repositories.hpp"
#include "fleetnav/storage/memory/memory_map_repository.hpp"

namespace fleetnav::server {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

/// Records what would be sent to the robots.
class RecordingMailbox : public RobotMailbox {
 public:
  bool SendAssignment(const std::string&, const JobAssignment&) override { return true; }
  bool SendCommand(const std::string&, const JobCommand&) override { return true; }
  bool SendClearance(const std::string& robot_id, const ClearanceNotice& clearance) override {
    sent[robot_id].push_back(clearance);
    return true;
  }
  void BroadcastMapUpdate(const std::string&, uint32_t, uint32_t) override {}
  std::map<std::string, std::vector<ClearanceNotice>> sent;
};

/// Two Lely robots on an empty 30 × 10 m hall; routes of straights and turns.
class TrafficCoordinatorTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(maps_
                    .PutMap("hall",
                            OccupancyGrid::Filled(600, 200, 0.05, Pose2(-15, -5, 0),
                                                  OccupancyGrid::kFreeValue)
                                .value(),
                            "", 0)
                    .ok());
  }

  /// Connects a robot standing at `pose` (telemetry in map).
  void Connect(const std::string& robot_id, const Pose2& pose,
               const RobotModel& model = LelyVectorModel(), bool segment_clearances = false,
               bool planned_paths = false) {
    RobotIdentity identity;
    identity.robot_id = robot_id;
    identity.model = model;
    identity.segment_clearances = segment_clearances;
    identity.planned_paths = planned_paths;
    sessions_[robot_id] = registry_.Connect(identity);
    Move(robot_id, pose);
  }

  /// The robot reports a new pose (telemetry in map), carrying `carried_load_m` on its lift.
  void Move(const std::string& robot_id, const Pose2& pose,
            const std::optional<Eigen::Vector2d>& carried_load_m = std::nullopt) {
    Telemetry telemetry;
    telemetry.pose_in_map = pose;
    telemetry.carried_load_m = carried_load_m;
    ASSERT_TRUE(registry_.RecordTelemetry(robot_id, sessions_[robot_id], telemetry).ok());
  }

  /// The robot reports a pose in action `action_index` of `job_id`.
  void MoveInJob(const std::string& robot_id, const Pose2& pose, const std::string& job_id,
                 int action_index) {
    Telemetry telemetry;
    telemetry.pose_in_map = pose;
    telemetry.job_id = job_id;
    telemetry.action_index = action_index;
    ASSERT_TRUE(registry_.RecordTelemetry(robot_id, sessions_[robot_id], telemetry).ok());
  }

  /// A coordinator over this fixture's site that looks for make-way places within `max_m`.
  std::unique_ptr<TrafficCoordinator> LookingForPlacesWithin(double max_m) {
    TrafficCoordinatorParams params = TrafficCoordinatorParams{};
    params.make_way.max_distance_m = max_m;
    return std::make_unique<TrafficCoordinator>(&site_data_, &registry_, &mailbox_, &clock_,
                                                params);
  }

  /// A free-navigation leg from (x_m, 0) to `distance_m` east of it.
  static FreeNavigationAction GoEast(double x_m, double distance_m) {
    return FreeNavigationAction{{}, Pose2(x_m + distance_m, 0.0, 0.0), 0.5, {}};
  }

  /// A laser-localized platform `a` at (-9, 0) and `b` (`b_model`; standing at gates when
  /// `b_gates`) 4 m behind it are sent 20 m east; a then drives 7 m, reporting every 0.5 m.
  void FollowEast(const RobotModel& b_model, bool b_gates) {
    Connect("a", Pose2(-9, 0, 0), MecanumPlatformModel(), true);
    Connect("b", Pose2(-13, 0, 0), b_model, b_gates);
    coordinator_.Begin("a", Job("job-a", {{GoEast(-9, 20.0), {}}}));
    clock_.AdvanceNs(1'000'000'000);
    coordinator_.Begin("b", Job("job-b", {{GoEast(-13, 20.0), {}}}));
    coordinator_.Update();
    for (double x = -9; x <= -2.0; x += 0.5) {
      MoveInJob("a", Pose2(x, 0, 0), "job-a", 0);
      clock_.AdvanceNs(500'000'000);
      coordinator_.Update();
    }
  }

  /// Lelys a at x = -6 and b at x = 6 are sent to each other's places (b's job a second
  /// later), and clearances are decided once.
  void BeginSwap() {
    Connect("a", Pose2(-6, 0, 0));
    Connect("b", Pose2(6, 0, kPi));
    coordinator_.Begin("a", Job("job-a", {{StraightAction{12.0, 0.5}, {}}}));
    clock_.AdvanceNs(1'000'000'000);
    coordinator_.Begin("b", Job("job-b", {{StraightAction{12.0, 0.5}, {}}}));
    coordinator_.Update();
  }

  JobAssignment Job(const std::string& job_id, std::vector<RouteAction> actions) {
    JobAssignment a;
    a.job.job_id = job_id;
    a.job.map_id = "hall";
    auto route = std::make_shared<Route>();
    route->name = job_id;
    route->map_id = "hall";
    route->actions = std::move(actions);
    a.route = std::move(route);
    a.map_version = 1;
    return a;
  }

  std::map<std::string, uint64_t> sessions_;
  storage::MemoryMapRepository maps_;
  storage::MemoryMarkerSetRepository markers_;
  ManualClock clock_{1'000'000'000};
  FleetRegistry registry_{&clock_, FleetRegistryParams{}};
  RecordingMailbox mailbox_;
  storage::MemoryRouteRepository routes_;
  SiteCache site_data_{&maps_, &markers_, &routes_};
  TrafficCoordinator coordinator_{&site_data_, &registry_, &mailbox_, &clock_,
                                  TrafficCoordinatorParams{}};
};

TEST_F(TrafficCoordinatorTest, CrossingRobotsAreClearedOneAfterTheOtherAndToldWhy) {
  // a drives 12 m east along y = 0 through x = 0; b waits north of it and then drives 8 m
  // south across the same place, expected later.
  Connect("a", Pose2(-8, 0, 0));
  Connect("b", Pose2(0, 4.5, -kPi / 2));
  coordinator_.Begin("a", Job("job-a", {{StraightAction{12.0, 0.5}, {}}}));
  clock_.AdvanceNs(5'000'000'000);
  coordinator_.Begin("b", Job("job-b", {{StraightAction{8.0, 0.5}, {}}}));
  const std::vector<TrafficWaitChange> changes = coordinator_.Update();
  ASSERT_EQ(mailbox_.sent["a"].size(), 1u);
  EXPECT_EQ(mailbox_.sent["a"].back().cleared_up_to_action, 0);
  ASSERT_EQ(mailbox_.sent["b"].size(), 1u);
  EXPECT_EQ(mailbox_.sent["b"].back().cleared_up_to_action, -1);
  EXPECT_THAT(mailbox_.sent["b"].back().wait_reason, HasSubstr("waits for a to finish action 0"));
  ASSERT_EQ(changes.size(), 1u);
  EXPECT_EQ(changes[0].job_id, "job-b");
  EXPECT_EQ(registry_.Get("b")->traffic_wait, changes[0].reason);

  // Nothing changed: nothing is sent again.
  coordinator_.Update();
  EXPECT_EQ(mailbox_.sent["b"].size(), 1u);

  // a finished its action and its job: b may go, and is no longer held.
  coordinator_.OnActionFinished("a", "job-a", 0);
  coordinator_.End("job-a");
  coordinator_.Update();
  EXPECT_EQ(mailbox_.sent["b"].back().cleared_up_to_action, 0);
  EXPECT_EQ(registry_.Get("b")->traffic_wait, "");
}

// With the search thread, a job's prediction is taken up by a later Update than the one that gave
// it, whatever the thread's speed (so a simulated run replays exactly), and meanwhile its robot
// stands as a robot without a job does: nobody is cleared through it.
TEST_F(TrafficCoordinatorTest,
       OnTheSearchThreadAPredictionIsTakenUpLaterAndItsRobotStandsMeanwhile) {
  coordinator_.StartSearchThread({});
  // b, 4 m north of a, is sent 8 m south across where a stands.
  Connect("a", Pose2(-8, 0, 0));
  Connect("b", Pose2(-8, 4, -kPi / 2));
  coordinator_.Begin("b", Job("job-b", {{StraightAction{8.0, 0.5}, {}}}));
  coordinator_.Update();
  EXPECT_TRUE(mailbox_.sent["b"].empty());  // its prediction is not yet taken up
  EXPECT_TRUE(coordinator_.SearchesPending());
  coordinator_.WaitForSearches();
  clock_.AdvanceNs(100'000'000);
  coordinator_.Update();
  ASSERT_EQ(mailbox_.sent["b"].size(), 1u);
  EXPECT_EQ(mailbox_.sent["b"].back().cleared_up_to_action, -1);
  EXPECT_THAT(mailbox_.sent["b"].back().wait_reason, HasSubstr("a, which stands in its way"));
  // a's job begins, going east: until its prediction is taken up a still stands in b's way.
  coordinator_.TakeMakeWayRequests();  // a, then without a job, was asked to make way
  coordinator_.Begin("a", Job("job-a", {{StraightAction{12.0, 0.5}, {}}}));
  coordinator_.Update();
  EXPECT_TRUE(mailbox_.sent["a"].empty());
  EXPECT_EQ(mailbox_.sent["b"].back().cleared_up_to_action, -1);
  EXPECT_TRUE(coordinator_.TakeMakeWayRequests().empty());  // with a job, it is not sent aside
  coordinator_.WaitForSearches();
  clock_.AdvanceNs(100'000'000);
  coordinator_.Update();
  EXPECT_FALSE(coordinator_.SearchesPending());
  ASSERT_EQ(mailbox_.sent["a"].size(), 1u);
  EXPECT_EQ(mailbox_.sent["a"].back().cleared_up_to_action, 0);
  EXPECT_THAT(mailbox_.sent["b"].back().wait_reason, HasSubstr("waits for a to finish action 0"));
  coordinator_.StopSearchThread();
  EXPECT_EQ(coordinator_.search_cpu().count, 2);
}

TEST_F(TrafficCoordinatorTest, AnAgentThatStandsAtGatesFollowsAnotherOneSegmentBehind) {
  // Two laser-localized platforms go to goals 20 m east along y = 0, b 4 m behind a. b's agent
  // stands at segment gates: it is cleared into its free-navigation leg up to a gate behind a,
  // not held for all of a's leg.
  FollowEast(MecanumPlatformModel(), true);
  ASSERT_FALSE(mailbox_.sent["a"].empty());
  EXPECT_EQ(mailbox_.sent["a"].front().cleared_up_to_action, 0);
  EXPECT_FALSE(mailbox_.sent["a"].front().hold.has_value());  // nothing holds a
  // a has driven 8 m: b is cleared into the action up to a gate that is behind a.
  ASSERT_FALSE(mailbox_.sent["b"].empty());
  const ClearanceNotice& b = mailbox_.sent["b"].back();
  EXPECT_EQ(b.cleared_up_to_action, 0) << b.wait_reason;
  ASSERT_TRUE(b.hold.has_value());
  EXPECT_EQ(b.hold->action_index, 0);
  EXPECT_GT(b.hold->gate.x_m(), -9.0);
  EXPECT_LT(b.hold->gate.x_m(), -2.0 - 1.5);       // a's rear, less the footprints and margins
  EXPECT_NEAR(b.hold->gate.yaw_rad(), 0.0, 1e-6);  // the direction of travel
  EXPECT_THAT(b.wait_reason, HasSubstr("waits for a to finish segment"));
  EXPECT_THAT(b.wait_reason, HasSubstr("of action 0 (free_navigation)"));
  EXPECT_EQ(b.waits.front().from_action, 0);  // told in actions
}

TEST_F(TrafficCoordinatorTest, AnAgentWithoutGatesIsClearedWholeActionsOnly) {
  // The same, but b's agent does not stand at gates: it waits for a's whole action.
  FollowEast(MecanumPlatformModel(), false);
  ASSERT_FALSE(mailbox_.sent["b"].empty());
  EXPECT_EQ(mailbox_.sent["b"].back().cleared_up_to_action, -1);
  EXPECT_FALSE(mailbox_.sent["b"].back().hold.has_value());
  // a has passed all its gates; b goes once a has finished the action (and stands at its end).
  MoveInJob("a", Pose2(11, 0, 0), "job-a", 0);
  coordinator_.OnActionFinished("a", "job-a", 0);
  coordinator_.Update();
  EXPECT_EQ(mailbox_.sent["b"].back().cleared_up_to_action, 0);
}

// The Lely localizes with ultrasonics and markers, not a laser: its estimate drifts by up to half
// a metre, more than a segment's slack. The Ackermann robot's tracking cuts corners of its own
// hybrid path. Both follow whole actions though their agents stand at gates.
class WholeActionsTest : public TrafficCoordinatorTest,
                         public ::testing::WithParamInterface<RobotModel> {};

TEST_P(WholeActionsTest, ARobotThatCannotFollowCloselyIsClearedWholeActions) {
  FollowEast(GetParam(), true);
  ASSERT_FALSE(mailbox_.sent["b"].empty());
  EXPECT_EQ(mailbox_.sent["b"].back().cleared_up_to_action, -1);
  EXPECT_FALSE(mailbox_.sent["b"].back().hold.has_value());
}

INSTANTIATE_TEST_SUITE_P(LelyAndAckermann, WholeActionsTest,
                         ::testing::Values(LelyVectorModel(), AckermannDeliveryModel()),
                         [](const auto& info) { return info.index == 0 ? "Lely" : "Ackermann"; });

TEST_F(TrafficCoordinatorTest, WhereARobotStandsGrowsWithItsPositionUncertainty) {
  // A platform stands 1.33 m beside another's way. Well localized (σ 2 cm), it stands off the
  // way; with σ 20 cm its standing place grows by 0.5 m and the other waits for it.
  Connect("a", Pose2(-8, 0, 0), MecanumPlatformModel());
  Connect("idle", Pose2(0, 1.33, 0), MecanumPlatformModel());
  const auto stand_with_sigma = [&](double sigma_m) {
    Telemetry telemetry;
    telemetry.pose_in_map = Pose2(0, 1.33, 0);
    telemetry.covariance[0] = telemetry.covariance[4] = sigma_m * sigma_m;
    ASSERT_TRUE(registry_.RecordTelemetry("idle", sessions_["idle"], telemetry).ok());
  };
  stand_with_sigma(0.02);
  coordinator_.Begin("a", Job("job-a1", {{StraightAction{12.0, 0.3}, {}}}));
  coordinator_.Update();
  ASSERT_FALSE(mailbox_.sent["a"].empty());
  EXPECT_EQ(mailbox_.sent["a"].back().cleared_up_to_action, 0);
  coordinator_.End("job-a1");
  stand_with_sigma(0.2);
  coordinator_.Begin("a", Job("job-a2", {{StraightAction{12.0, 0.3}, {}}}));
  coordinator_.Update();
  EXPECT_EQ(mailbox_.sent["a"].back().cleared_up_to_action, -1);
  EXPECT_THAT(mailbox_.sent["a"].back().wait_reason, HasSubstr("idle, which stands in its way"));
}

TEST_F(TrafficCoordinatorTest, WhatARobotSweepsGrowsWithItsOwnUncertaintyAndItsKind) {
  // A platform stands 1.2 m beside the way of another (σ 2 cm). The other, well localized
  // (σ 2 cm), sweeps its footprint grown by 0.3 m and passes; unsure (σ 13 cm), by 0.49 m, and
  // waits for it; a Lely, drifting between markers, by the whole 0.5 m whatever it reports.
  Connect("idle", Pose2(0, 1.2, 0), MecanumPlatformModel());
  const auto drive_with_sigma = [&](const std::string& robot_id, const RobotModel& model,
                                    double sigma_m) {
    Connect(robot_id, Pose2(-8, 0, 0), model);
    Telemetry telemetry;
    telemetry.pose_in_map = Pose2(-8, 0, 0);
    telemetry.covariance[0] = telemetry.covariance[4] = sigma_m * sigma_m;
    ASSERT_TRUE(registry_.RecordTelemetry(robot_id, sessions_[robot_id], telemetry).ok());
    coordinator_.Begin(robot_id, Job("job-" + robot_id, {{StraightAction{12.0, 0.3}, {}}}));
    coordinator_.Update();
    coordinator_.End("job-" + robot_id);
    registry_.Disconnect(robot_id, sessions_[robot_id]);
  };
  drive_with_sigma("sure", MecanumPlatformModel(), 0.02);
  ASSERT_FALSE(mailbox_.sent["sure"].empty());
  EXPECT_EQ(mailbox_.sent["sure"].back().cleared_up_to_action, 0);
  drive_with_sigma("unsure", MecanumPlatformModel(), 0.13);
  ASSERT_FALSE(mailbox_.sent["unsure"].empty());
  EXPECT_EQ(mailbox_.sent["unsure"].back().cleared_up_to_action, -1);
  EXPECT_THAT(mailbox_.sent["unsure"].back().wait_reason,
              HasSubstr("idle, which stands in its way"));
  drive_with_sigma("lely", LelyVectorModel(), 0.02);
  ASSERT_FALSE(mailbox_.sent["lely"].empty());
  EXPECT_EQ(mailbox_.sent["lely"].back().cleared_up_to_action, -1);
}

TEST_F(TrafficCoordinatorTest, ARobotOffItsPredictionIsWaitedForWhereItIsNotWhereItWasPlanned) {
  // a is sent 14 m east; b, whose way ends 6 m north of a's way, has been cleared and
  // predicted to stand there, but reports itself on a's way (it drove off its prediction).
  Connect("b", Pose2(0, 6, kPi / 2), MecanumPlatformModel(), true);
  coordinator_.Begin("b", Job("job-b", {{StraightAction{0.5, 0.3}, {}}}));
  coordinator_.Update();
  ASSERT_EQ(mailbox_.sent["b"].back().cleared_up_to_action, 0);
  MoveInJob("b", Pose2(0, 0.3, kPi / 2), "job-b", 0);
  Connect("a", Pose2(-8, 0, 0), MecanumPlatformModel(), true);
  clock_.AdvanceNs(500'000'000);
  coordinator_.Begin("a", Job("job-a", {{StraightAction{14.0, 0.3}, {}}}));
  coordinator_.Update();
  ASSERT_FALSE(mailbox_.sent["a"].empty());
  EXPECT_EQ(mailbox_.sent["a"].back().cleared_up_to_action, -1);
  EXPECT_THAT(mailbox_.sent["a"].back().wait_reason, HasSubstr("b, which stands in its way"));
  // Back where it was predicted, a goes.
  MoveInJob("b", Pose2(0, 6.5, kPi / 2), "job-b", 0);
  clock_.AdvanceNs(500'000'000);
  coordinator_.Update();
  EXPECT_EQ(mailbox_.sent["a"].back().cleared_up_to_action, 0);
}

TEST_F(TrafficCoordinatorTest, AnIdleRobotInTheWayIsNeverDrivenThrough) {
  Connect("a", Pose2(-8, 0, 0));
  Connect("idle", Pose2(0, 0, kPi / 2));  // no job: it stands on a's way
  coordinator_.Begin(
      "a", Job("job-a", {{StraightAction{4.0, 0.5}, {}}, {StraightAction{8.0, 0.5}, {}}}));
  coordinator_.Update();
  ASSERT_FALSE(mailbox_.sent["a"].empty());
  EXPECT_EQ(mailbox_.sent["a"].back().cleared_up_to_action, 0);
  EXPECT_THAT(mailbox_.sent["a"].back().wait_reason, HasSubstr("idle, which stands in its way"));
}

/// The closest of `path`'s waypoints to `point`.
double ClosestWaypointM(const ActionPath& path, const Eigen::Vector2d& point) {
  double closest_m = 1e9;
  for (const Eigen::Vector2d& p : path.waypoints_m) {
    closest_m = std::min(closest_m, (p - point).norm());
  }
  return closest_m;
}

TEST_F(TrafficCoordinatorTest, ARobotWaitingForOneThatStandsInItsWayIsPlannedAWayRoundIt) {
  // A platform that drives planned paths, sent 14 m east; a Lely stands without a job on the
  // way (it will not move by itself).
  Connect("a", Pose2(-8, 0, 0), MecanumPlatformModel(), /*segment_clearances=*/true,
          /*planned_paths=*/true);
  Connect("idle", Pose2(0, 0, kPi / 2));
  coordinator_.Begin("a", Job("job-a", {{GoEast(-8, 14.0), {}}}));
  coordinator_.Update();
  ASSERT_FALSE(mailbox_.sent["a"].empty());
  EXPECT_THAT(mailbox_.sent["a"].back().wait_reason, HasSubstr("idle, which stands in its way"));
  EXPECT_TRUE(mailbox_.sent["a"].back().paths.empty());
  clock_.AdvanceNs(500'000'000);
  coordinator_.Update();
  // Cleared along a way round it, told with the clearance.
  const ClearanceNotice& told = mailbox_.sent["a"].back();
  EXPECT_EQ(told.wait_reason, "");
  EXPECT_EQ(told.cleared_up_to_action, 0);
  ASSERT_EQ(told.paths.size(), 1u);
  EXPECT_EQ(told.paths[0].action_index, 0);
  // Abreast of the Lely the way keeps both footprints and the swept margin between them.
  EXPECT_GT(ClosestWaypointM(told.paths[0], {0, 0}), 1.0);
}

/// A stop of zone `pen` of map `map_id`: the box x in [-1, 1], y in [-1.5, 1.5].
RobotStop PenStop(const std::string& map_id = "hall") {
  RobotStop stop;
  stop.map_id = map_id;
  stop.zone = "pen";
  stop.polygon_in_map = {{-1, -1.5}, {1, -1.5}, {1, 1.5}, {-1, 1.5}};
  return stop;
}

/// The least distance from the legs through `path`'s waypoints (from `from` to `to`) to the
/// polygon, sampled every 5 cm.
double ClosestLegM(const Eigen::Vector2d& from, const ActionPath& path, const Eigen::Vector2d& to,
                   const Polygon2& polygon) {
  std::vector<Eigen::Vector2d> points = {from};
  points.insert(points.end(), path.waypoints_m.begin(), path.waypoints_m.end());
  points.push_back(to);
  double closest_m = 1e9;
  for (size_t k = 1; k < points.size(); ++k) {
    const double length_m = (points[k] - points[k - 1]).norm();
    for (double s = 0.0; s <= length_m; s += 0.05) {
      const Eigen::Vector2d p = points[k - 1] + (points[k] - points[k - 1]) * (s / length_m);
      closest_m = std::min(
          closest_m, PolygonContains(polygon, p) ? 0.0 : DistanceToPolygonBoundary(polygon, p));
    }
  }
  return closest_m;
}

TEST_F(TrafficCoordinatorTest, ARobotWhoseWayCrossesAStoppedZoneIsPlannedAWayRoundIt) {
  // A platform that drives planned paths, sent 14 m east along y = 0, is cleared straight on.
  const RobotModel model = MecanumPlatformModel();
  Connect("a", Pose2(-8, 0, 0), model, /*segment_clearances=*/true, /*planned_paths=*/true);
  coordinator_.Begin("a", Job("job-a", {{GoEast(-8, 14.0), {}}}));
  coordinator_.Update();
  ASSERT_FALSE(mailbox_.sent["a"].empty());
  EXPECT_TRUE(mailbox_.sent["a"].back().paths.empty());
  // A stop on another map changes nothing; the pen on its way stopped: a way round it.
  coordinator_.SetStops({PenStop("store")});
  clock_.AdvanceNs(500'000'000);
  coordinator_.Update();
  EXPECT_TRUE(mailbox_.sent["a"].back().paths.empty());
  coordinator_.SetStops({PenStop("store"), PenStop()});
  clock_.AdvanceNs(500'000'000);
  coordinator_.Update();  // searched
  clock_.AdvanceNs(500'000'000);
  coordinator_.Update();  // told
  const ClearanceNotice& told = mailbox_.sent["a"].back();
  ASSERT_EQ(told.paths.size(), 1u);
  EXPECT_EQ(told.paths[0].action_index, 0);
  EXPECT_EQ(told.cleared_up_to_action, 0);
  // Its centre keeps its body and a grown margin off the zone, so its agent never slows for
  // it (within a cell for the thinning of the way).
  EXPECT_GT(ClosestLegM({-8, 0}, told.paths[0], {6, 0}, PenStop().polygon_in_map),
            model.CircumscribedRadius() + 0.2 - 0.1);
}

TEST_F(TrafficCoordinatorTest, ARobotInAStoppedZoneOrBoundIntoItIsNotPlannedAWayRound) {
  // In the pen: it stands there. Sent into the pen: there is no way round to its goal.
  Connect("in", Pose2(0, 0, 0), MecanumPlatformModel(), true, true);
  Connect("into", Pose2(-8, 3, 0), MecanumPlatformModel(), true, true);
  coordinator_.Begin("in", Job("job-in", {{GoEast(0, 6.0), {}}}));
  coordinator_.Begin(
      "into", Job("job-into", {{FreeNavigationAction{{}, Pose2(0.0, 0.5, 0.0), 0.5, {}}, {}}}));
  coordinator_.SetStops({PenStop()});
  for (int i = 0; i < 3; ++i) {
    coordinator_.Update();
    clock_.AdvanceNs(11'000'000'000);  // past detour_every_s
  }
  for (const char* robot : {"in", "into"}) {
    ASSERT_FALSE(mailbox_.sent[robot].empty()) << robot;
    EXPECT_TRUE(mailbox_.sent[robot].back().paths.empty()) << robot;
  }
}

TEST_F(TrafficCoordinatorTest, ANoGoZonePutWhileRobotsDriveGetsTheOneItClosesAWayRoundAlone) {
  // Platforms a along y = 0 and b along y = 4, both 14 m east, given with no zones.
  storage::MemoryZoneSetRepository zone_store;
  ZoneCatalog zones(&zone_store, &site_data_, &clock_);
  RecordingMailbox mailbox;
  TrafficCoordinator coordinator(&site_data_, &registry_, &mailbox, &clock_, {});
  coordinator.UseZones(&zones);
  Connect("a", Pose2(-8, 0, 0), MecanumPlatformModel(), true, true);
  Connect("b", Pose2(-8, 4, 0), MecanumPlatformModel(), true, true);
  coordinator.Begin("a", Job("job-a", {{GoEast(-8, 14.0), {}}}));
  JobAssignment job_b = Job("job-b", {{FreeNavigationAction{{}, Pose2(6, 4, 0), 0.5, {}}, {}}});
  coordinator.Begin("b", job_b);
  coordinator.Update();
  ASSERT_FALSE(mailbox.sent["a"].empty());
  ASSERT_FALSE(mailbox.sent["b"].empty());
  // A spill on a's way is closed.
  ZoneSet closed;
  closed.map_id = "hall";
  closed.zones.push_back(
      {"spill", ZoneKind::kNoGo, {{-1, -1.5}, {1, -1.5}, {1, 1.5}, {-1, 1.5}}, 0.0, 1});
  ASSERT_TRUE(zones.PutZones(closed).ok());
  coordinator.ZonesChanged();
  for (int i = 0; i < 2; ++i) {
    clock_.AdvanceNs(100'000'000);
    coordinator.Update();
  }
  ASSERT_FALSE(mailbox.sent["a"].back().paths.empty());
  EXPECT_GT(ClosestLegM({-8, 0}, mailbox.sent["a"].back().paths[0], {6, 0},
                        closed.zones[0].polygon_in_map),
            MecanumPlatformModel().CircumscribedRadius());
  // b's way keeps clear of the spill: its way is left as it was (0 churn).
  for (const ClearanceNotice& told : mailbox.sent["b"]) EXPECT_TRUE(told.paths.empty());
}

TEST_F(TrafficCoordinatorTest, AZoneAddedElsewhereLeavesARobotPlannedRoundTheOldOnesUntouched) {
  // The hall closed south of y = 2.5 between x = -2 and 2 (version 1): a platform given that
  // version is planned round it, close by its edge.
  storage::MemoryZoneSetRepository zone_store;
  ZoneCatalog zones(&zone_store, &site_data_, &clock_);
  ZoneSet v1;
  v1.map_id = "hall";
  v1.zones.push_back({"spill", ZoneKind::kNoGo, {{-2, -5}, {2, -5}, {2, 2.5}, {-2, 2.5}}, 0.0, 1});
  ASSERT_TRUE(zones.PutZones(v1).ok());
  RecordingMailbox mailbox;
  TrafficCoordinator coordinator(&site_data_, &registry_, &mailbox, &clock_, {});
  coordinator.UseZones(&zones);
  Connect("d", Pose2(-8, 0, 0), MecanumPlatformModel(), true, true);
  JobAssignment job = Job("job-d", {{GoEast(-8, 16.0), {}}});
  job.zone_set_version = 1;
  coordinator.Begin("d", job);
  coordinator.Update();
  ASSERT_FALSE(mailbox.sent["d"].empty());
  // Version 2 adds a zone far off its way: its way stays as it is.
  ZoneSet v2 = v1;
  v2.zones.push_back({"dock", ZoneKind::kNoGo, {{12, -4}, {14, -4}, {14, -3}, {12, -3}}, 0.0, 1});
  ASSERT_TRUE(zones.PutZones(v2).ok());
  coordinator.ZonesChanged();
  for (int i = 0; i < 3; ++i) {
    clock_.AdvanceNs(100'000'000);
    coordinator.Update();
  }
  for (const ClearanceNotice& told : mailbox.sent["d"]) EXPECT_TRUE(told.paths.empty());
}

TEST_F(TrafficCoordinatorTest, AFreeNavigationLegIsPredictedRoundTheNoGoZonesAsItsAgentDrives) {
  // A platform sent 16 m east along y = 0; a Lely stands without a job 3.5 m north of its way.
  // On the map alone the way keeps far off the Lely: cleared.
  Connect("a", Pose2(-8, 0, 0), MecanumPlatformModel());
  Connect("idle", Pose2(0, 3.5, 0));
  coordinator_.Begin("a", Job("job-a", {{GoEast(-8, 16.0), {}}}));
  coordinator_.Update();
  ASSERT_FALSE(mailbox_.sent["a"].empty());
  EXPECT_EQ(mailbox_.sent["a"].back().cleared_up_to_action, 0);
  EXPECT_EQ(mailbox_.sent["a"].back().wait_reason, "");
  // A no-go zone closes the hall south of y = 2.5 between x = -2 and 2: the agent plans round
  // it, past the Lely, so must the prediction, which then finds the Lely in the way.
  storage::MemoryZoneSetRepository zone_store;
  ZoneCatalog zones(&zone_store, &site_data_, &clock_);
  ZoneSet closed;
  closed.map_id = "hall";
  closed.zones.push_back(
      {"spill", ZoneKind::kNoGo, {{-2, -5}, {2, -5}, {2, 2.5}, {-2, 2.5}}, 0.0, 1});
  ASSERT_TRUE(zones.PutZones(closed).ok());
  RecordingMailbox mailbox;
  TrafficCoordinator coordinator(&site_data_, &registry_, &mailbox, &clock_,
                                 TrafficCoordinatorParams{});
  coordinator.UseZones(&zones);
  coordinator.Begin("a", Job("job-a", {{GoEast(-8, 16.0), {}}}));
  coordinator.Update();
  ASSERT_FALSE(mailbox.sent["a"].empty());
  EXPECT_EQ(mailbox.sent["a"].back().cleared_up_to_action, -1);
  EXPECT_THAT(mailbox.sent["a"].back().wait_reason, HasSubstr("idle"));
}

TEST_F(TrafficCoordinatorTest, ARobotUnderWayStandsWhereItIsUntilItsNewWayIsCleared) {
  // A Lely cleared first crosses the platform's way and ends on it.
  Connect("c", Pose2(0, -3, kPi / 2));
  coordinator_.Begin("c", Job("job-c", {{StraightAction{3.0, 0.5}, {}}}));
  coordinator_.Update();
  Connect("a", Pose2(-8, 0, 0), MecanumPlatformModel(), /*segment_clearances=*/true,
          /*planned_paths=*/true);
  clock_.AdvanceNs(500'000'000);
  coordinator_.Begin("a", Job("job-a", {{GoEast(-8, 14.0), {}}}));
  coordinator_.Update();
  ASSERT_TRUE(mailbox_.sent["a"].back().hold.has_value())
      << mailbox_.sent["a"].back().cleared_up_to_action << " "
      << mailbox_.sent["a"].back().wait_reason;
  const double gate_x_m = mailbox_.sent["a"].back().hold->gate.x_m();
  ASSERT_LT(gate_x_m, -1.0);
  // The Lely ends its job where it crossed: it stands in the way of the platform under way.
  Move("c", Pose2(0, 0, kPi / 2));
  coordinator_.End("job-c");
  clock_.AdvanceNs(500'000'000);
  coordinator_.Update();
  EXPECT_THAT(mailbox_.sent["a"].back().wait_reason, HasSubstr("c, which stands in its way"));
  for (double x = -8.0; x <= gate_x_m + 0.3 && mailbox_.sent["a"].back().paths.empty(); x += 0.25) {
    MoveInJob("a", Pose2(std::min(x, gate_x_m), 0, 0), "job-a", 0);
    clock_.AdvanceNs(500'000'000);
    coordinator_.Update();
  }
  // Told the way round with its clearance along it, from where it stands.
  const std::vector<ClearanceNotice>& sent = mailbox_.sent["a"];
  auto told = std::find_if(sent.begin(), sent.end(),
                           [](const ClearanceNotice& n) { return !n.paths.empty(); });
  ASSERT_NE(told, sent.end());
  EXPECT_EQ(told->cleared_up_to_action, 0);
  EXPECT_EQ(told->wait_reason, "");
  EXPECT_GT(ClosestWaypointM(told->paths[0], {0, 0}), 1.0);
  EXPECT_GT((told->paths[0].waypoints_m.front() - Eigen::Vector2d(gate_x_m, 0)).norm(), 0.5);
  // Told again with each later clearance: the same way.
  MoveInJob("a", Pose2(gate_x_m + 0.5, 0.3, 0), "job-a", 0);
  clock_.AdvanceNs(500'000'000);
  coordinator_.Update();
  ASSERT_FALSE(sent.back().paths.empty());
  EXPECT_EQ(sent.back().paths[0].id, told->paths[0].id);
}

TEST_F(TrafficCoordinatorTest, ARouteHeldWholeIsPlannedAWayRoundTheRobotItCouldNotBeOrderedWith) {
  // a (an older agent: no planned paths) is sent east from (-6, 0); w stands on its way at
  // (0, 0) and is sent west past a's start. Each stands where the other must go: w's job,
  // the newer, is held whole. A way round a lets w go first, and a follows.
  Connect("a", Pose2(-6, 0, 0), MecanumPlatformModel(), true, false);
  Connect("w", Pose2(0, 0, kPi / 2), MecanumPlatformModel(), true, true);
  coordinator_.Begin("a", Job("job-a", {{GoEast(-6, 12.0), {}}}));
  clock_.AdvanceNs(500'000'000);
  coordinator_.Begin("w",
                     Job("job-w", {{FreeNavigationAction{{}, Pose2(-9, 0, kPi), 0.5, {}}, {}}}));
  coordinator_.Update();
  ASSERT_FALSE(mailbox_.sent["w"].empty());
  EXPECT_THAT(mailbox_.sent["w"].back().wait_reason, HasSubstr("block each other"));
  clock_.AdvanceNs(500'000'000);
  coordinator_.Update();
  const ClearanceNotice& w = mailbox_.sent["w"].back();
  EXPECT_EQ(w.cleared_up_to_action, 0) << w.wait_reason;
  ASSERT_EQ(w.paths.size(), 1u);
  EXPECT_GT(ClosestWaypointM(w.paths[0], {-6, 0}), 1.0);
  EXPECT_THAT(mailbox_.sent["a"].back().wait_reason, HasSubstr("w"));
}

// A robot at the end of a dead-end corridor can leave only past the robot under way to its place,
// which stands at its gate in the corridor: sending the first aside again and again cannot break
// the circle (in a generated dense hall one was sent to a new place every 20 s for half an hour).
// The one under way steps aside within its action instead, through a place off the other's way.
TEST_F(TrafficCoordinatorTest, ARobotUnderWayStepsAsideForOneThatCanLeaveOnlyPastIt) {
  // A corridor 1.2 m wide from x = 2 to 8 m along y = 0, closed at its east end.
  OccupancyGrid grid =
      OccupancyGrid::Filled(600, 200, 0.05, Pose2(-15, -5, 0), OccupancyGrid::kFreeValue).value();
  for (double x = 2.0; x < 8.6; x += 0.05) {
    for (double y = -1.2; y < 1.2; y += 0.05) {
      if (std::abs(y) >= 0.6 || x >= 8.2) {
        grid.SetValue(*grid.WorldToCell({x + 0.025, y + 0.025}), OccupancyGrid::kOccupiedValue);
      }
    }
  }
  ASSERT_TRUE(maps_.PutMap("hall", grid, "", 0).ok());  // version 2
  const auto on_version_2 = [&](JobAssignment job) {
    job.map_version = 2;
    return job;
  };
  Connect("a", Pose2(-4, 0, 0), MecanumPlatformModel(), true, true);
  Connect("b", Pose2(7.4, 0, kPi), MecanumPlatformModel(), true, true);
  // a is sent to the corridor's mouth, then on to where b stands: it drives the first leg and
  // stands there, under way.
  coordinator_.Begin("a",
                     on_version_2(Job("job-a", {{GoEast(-4, 4.0), {}}, {GoEast(0, 7.4), {}}})));
  coordinator_.Update();
  coordinator_.TakeMakeWayRequests();  // b, then without a job, was asked to make way
  ASSERT_FALSE(mailbox_.sent["a"].empty());
  ASSERT_EQ(mailbox_.sent["a"].back().cleared_up_to_action, 0);
  const double gate_x_m = 0.0;
  MoveInJob("a", Pose2(gate_x_m, 0, 0), "job-a", 0);
  coordinator_.OnActionFinished("a", "job-a", 0);
  clock_.AdvanceNs(500'000'000);
  coordinator_.Update();
  EXPECT_THAT(mailbox_.sent["a"].back().wait_reason, HasSubstr("b, which stands in its way"));
  // b is then sent west, past a: its job, not begun, is held, and b is sent aside once.
  clock_.AdvanceNs(500'000'000);
  coordinator_.Begin(
      "b",
      on_version_2(Job("job-b", {{FreeNavigationAction{{}, Pose2(-10, 0, kPi), 0.5, {}}, {}}})));
  coordinator_.Update();
  EXPECT_THAT(mailbox_.sent["b"].back().wait_reason, HasSubstr("block each other"));
  std::vector<MakeWayRequest> asked = coordinator_.TakeMakeWayRequests();
  ASSERT_EQ(asked.size(), 1u);
  EXPECT_EQ(asked[0].robot_id, "b");
  EXPECT_TRUE(asked[0].breaks_wait_cycle);
  // b cannot leave: the circle stays. A period on, a steps aside instead of b going again.
  for (int second = 0; second < 21; ++second) {
    clock_.AdvanceNs(1'000'000'000);
    coordinator_.Resend("a");
    coordinator_.Update();
    asked = coordinator_.TakeMakeWayRequests();
    EXPECT_TRUE(std::none_of(asked.begin(), asked.end(), [](const MakeWayRequest& r) {
      return r.robot_id == "b";
    })) << second;
  }
  const std::vector<ClearanceNotice>& sent = mailbox_.sent["a"];
  auto told = std::find_if(sent.begin(), sent.end(),
                           [](const ClearanceNotice& n) { return !n.paths.empty(); });
  ASSERT_NE(told, sent.end());
  ASSERT_EQ(told->paths[0].waypoints_m.size(), 1u);
  const Eigen::Vector2d aside = told->paths[0].waypoints_m[0];
  EXPECT_LT(aside.x(), 2.0) << aside.transpose();  // outside the corridor
  // Told with its new window, cleared into the action along the new way.
  EXPECT_EQ(told->cleared_up_to_action, 1) << told->wait_reason;
  ASSERT_TRUE(told->hold.has_value());
  EXPECT_EQ(sent.back().paths[0].id, told->paths[0].id);  // told again with each clearance
}

TEST_F(TrafficCoordinatorTest, AnAgentWithoutPlannedPathsIsNeverPlannedAWayRound) {
  Connect("a", Pose2(-8, 0, 0), MecanumPlatformModel(), /*segment_clearances=*/true);
  Connect("idle", Pose2(0, 0, kPi / 2));
  coordinator_.Begin("a", Job("job-a", {{GoEast(-8, 14.0), {}}}));
  for (double x = -8.0; x <= -2.0; x += 0.25) {
    MoveInJob("a", Pose2(x, 0, 0), "job-a", 0);
    clock_.AdvanceNs(500'000'000);
    coordinator_.Update();
  }
  for (const ClearanceNotice& notice : mailbox_.sent["a"]) EXPECT_TRUE(notice.paths.empty());
  EXPECT_THAT(mailbox_.sent["a"].back().wait_reason, HasSubstr("idle, which stands in its way"));
}

/// Whether a Lely standing at `place` would be in the way of one driving along y = 0 from
/// x = from_x_m for 12 m, as traffic coordination sweeps both (footprint grown by margin_m).
bool InTheWayOfTwelveMetresEastFrom(double from_x_m, const Pose2& place) {
  const TrafficCoordinatorParams params;
  std::vector<Pose2> way;
  for (int i = 0; i <= 120; ++i) way.emplace_back(from_x_m + 0.1 * i, 0.0, 0.0);
  const std::vector<Eigen::Vector2d>& footprint = LelyVectorModel().footprint_m;
  // Where it stands is grown by the standing margin (its position is known to a few cm).
  return planner::CellSet::Sweep({place}, footprint, params.standing_margin_min_m, params.cell_m)
      .Intersects(planner::CellSet::Sweep(way, footprint, params.margin_m, params.cell_m));
}

TEST_F(TrafficCoordinatorTest, AnIdleRobotInTheWayIsAskedOnceToMakeWayToAPlaceOffTheWay) {
  Connect("a", Pose2(-8, 0, 0));
  Connect("idle", Pose2(0, 0, kPi / 2));
  coordinator_.Begin("a", Job("job-a", {{StraightAction{12.0, 0.5}, {}}}));
  coordinator_.Update();
  const std::vector<MakeWayRequest> requests = coordinator_.TakeMakeWayRequests();
  ASSERT_EQ(requests.size(), 1u);
  EXPECT_EQ(requests[0].robot_id, "idle");
  EXPECT_EQ(requests[0].map_id, "hall");
  EXPECT_EQ(requests[0].for_robot_id, "a");
  // The place is off a's way as traffic coordination sweeps it.
  EXPECT_FALSE(InTheWayOfTwelveMetresEastFrom(-8.0, requests[0].place));
  // Beside the way, not down the hall: the nearest such place.
  EXPECT_LT((requests[0].place.translation() - Eigen::Vector2d(0, 0)).norm(), 4.0);

  // Asked once: not again while it has not had a job since.
  clock_.AdvanceNs(1'000'000'000);
  coordinator_.Update();
  EXPECT_TRUE(coordinator_.TakeMakeWayRequests().empty());
  // Given a job (the make-way job) and back to idle in the way: asked again.
  coordinator_.Begin("idle", Job("job-idle", {{StraightAction{0.1, 0.5}, {}}}));
  coordinator_.End("job-idle");
  coordinator_.Update();
  EXPECT_EQ(coordinator_.TakeMakeWayRequests().size(), 1u);
}

TEST_F(TrafficCoordinatorTest, AnIdleRobotWithNowhereToGoIsNamedInTheWaitingRobotsReason) {
  const std::unique_ptr<TrafficCoordinator> owned = LookingForPlacesWithin(0.3);
  TrafficCoordinator& coordinator = *owned;
  Connect("a", Pose2(-8, 0, 0));
  Connect("idle", Pose2(0, 0, kPi / 2));
  coordinator.Begin("a", Job("job-a", {{StraightAction{12.0, 0.5}, {}}}));
  coordinator.Update();
  EXPECT_TRUE(coordinator.TakeMakeWayRequests().empty());
  ASSERT_FALSE(mailbox_.sent["a"].empty());
  EXPECT_EQ(mailbox_.sent["a"].back().cleared_up_to_action, -1);
  EXPECT_THAT(mailbox_.sent["a"].back().wait_reason,
              HasSubstr("idle, which stands in its way; it cannot make way: no place within "
                        "0.3 m of (0.00, 0.00)"));
}

TEST_F(TrafficCoordinatorTest, OfTwoRobotsSwappingPlacesTheNewerJobIsWithdrawnAndItsRobotMakesWay) {
  // a at x = -6 goes to x = 6 where b stands; b goes to x = -6 where a stands. Neither order
  // works at action granularity: b's job, the newer, is held, and b stands in a's way.
  BeginSwap();
  EXPECT_EQ(mailbox_.sent["a"].back().cleared_up_to_action, -1);
  EXPECT_EQ(mailbox_.sent["b"].back().cleared_up_to_action, -1);
  const std::vector<MakeWayRequest> requests = coordinator_.TakeMakeWayRequests();
  ASSERT_EQ(requests.size(), 1u);
  EXPECT_EQ(requests[0].robot_id, "b");
  EXPECT_EQ(requests[0].for_robot_id, "a");
  EXPECT_EQ(requests[0].withdraw_job_id, "job-b");
  // a waits for b standing and b's held job for a: a circle of waits, which b breaks.
  EXPECT_TRUE(requests[0].breaks_wait_cycle);
  // Its place is off a's way and off where a ends.
  EXPECT_FALSE(InTheWayOfTwelveMetresEastFrom(-6.0, requests[0].place));

  // b's job withdrawn, b aside: a goes.
  coordinator_.End("job-b");
  Move("b", requests[0].place);
  clock_.AdvanceNs(1'000'000'000);
  coordinator_.Update();
  EXPECT_EQ(mailbox_.sent["a"].back().cleared_up_to_action, 0);
}

TEST_F(TrafficCoordinatorTest, ACircleOfWaitsThatStaysIsBrokenOncePerPeriodByTurns) {
  // The swap above, but nobody is withdrawn or moves: the circle stays.
  BeginSwap();
  ASSERT_EQ(coordinator_.TakeMakeWayRequests().size(), 1u);
  // A second later, decided again: the requests made.
  const auto next_second = [&] {
    clock_.AdvanceNs(1'000'000'000);
    coordinator_.Resend("a");
    coordinator_.Update();
    return coordinator_.TakeMakeWayRequests();
  };
  // Within break_cycle_every_s (20 s) b is not sent aside again, however often it is decided.
  for (int i = 0; i < 19; ++i) EXPECT_TRUE(next_second().empty()) << i;
  // The circle stayed although b was sent aside: now the other robot of it goes aside.
  const std::vector<MakeWayRequest> again = next_second();
  ASSERT_EQ(again.size(), 1u);
  EXPECT_EQ(again[0].robot_id, "a");
  EXPECT_EQ(again[0].withdraw_job_id, "job-a");
  EXPECT_TRUE(again[0].breaks_wait_cycle);
  // And then b again, another period on.
  for (int i = 0; i < 19; ++i) EXPECT_TRUE(next_second().empty()) << i;
  const std::vector<MakeWayRequest> third = next_second();
  ASSERT_EQ(third.size(), 1u);
  EXPECT_EQ(third[0].robot_id, "b");
}

TEST_F(TrafficCoordinatorTest, AnIdleRobotWithNoPlaceLooksAgainOnceAJobHasEnded) {
  // a drives along y = 0 through the idle robot; b and c stand north and south of it with
  // jobs along y = +-3, so within 3 m there is no place off every way.
  const std::unique_ptr<TrafficCoordinator> owned = LookingForPlacesWithin(3.0);
  TrafficCoordinator& coordinator = *owned;
  Connect("a", Pose2(-8, 0, 0));
  Connect("idle", Pose2(0, 0, kPi / 2));
  Connect("b", Pose2(-4, 3, 0));
  Connect("c", Pose2(-4, -3, 0));
  coordinator.Begin("a", Job("job-a", {{StraightAction{12.0, 0.5}, {}}}));
  coordinator.Begin("b", Job("job-b", {{StraightAction{8.0, 0.5}, {}}}));
  coordinator.Begin("c", Job("job-c", {{StraightAction{8.0, 0.5}, {}}}));
  coordinator.Update();
  EXPECT_TRUE(coordinator.TakeMakeWayRequests().empty());
  EXPECT_THAT(mailbox_.sent["a"].back().wait_reason, HasSubstr("it cannot make way"));
  // b's job ends (b has driven on, east of the hall's middle): the north side is free.
  coordinator.End("job-b");
  Move("b", Pose2(8, 3, 0));
  coordinator.Update();
  const std::vector<MakeWayRequest> requests = coordinator.TakeMakeWayRequests();
  ASSERT_EQ(requests.size(), 1u);
  EXPECT_EQ(requests[0].robot_id, "idle");
  EXPECT_GT(requests[0].place.y_m(), 1.0);
  EXPECT_FALSE(InTheWayOfTwelveMetresEastFrom(-8.0, requests[0].place));
}

// When no job began, ended or moved on, the clearances are decided again only once
// recheck_period_s has passed: an idle robot that walked out of the way is noticed then.
TEST_F(TrafficCoordinatorTest, WithoutJobEventsClearancesAreRecheckedOncePerPeriod) {
  Connect("a", Pose2(-8, 0, 0));
  Connect("idle", Pose2(0, 0, kPi / 2));
  coordinator_.Begin(
      "a", Job("job-a", {{StraightAction{4.0, 0.5}, {}}, {StraightAction{8.0, 0.5}, {}}}));
  coordinator_.Update();
  ASSERT_EQ(mailbox_.sent["a"].size(), 1u);
  EXPECT_EQ(mailbox_.sent["a"].back().cleared_up_to_action, 0);
  Move("idle", Pose2(0, 6, kPi / 2));
  coordinator_.Update();  // within the period: not looked at
  EXPECT_EQ(mailbox_.sent["a"].size(), 1u);
  clock_.AdvanceNs(static_cast<int64_t>(TrafficCoordinatorParams{}.recheck_period_s * 1e9) + 1);
  coordinator_.Update();
  ASSERT_EQ(mailbox_.sent["a"].size(), 2u);
  EXPECT_EQ(mailbox_.sent["a"].back().cleared_up_to_action, 1);
  EXPECT_EQ(mailbox_.sent["a"].back().wait_reason, "");
}

// A job event (here the end of another robot's job) is decided on at once.
TEST_F(TrafficCoordinatorTest, AJobEndingIsDecidedOnAtOnce) {
  Connect("a", Pose2(-8, 0, 0));
  Connect("b", Pose2(0, 0, kPi / 2));
  coordinator_.Begin(
      "a", Job("job-a", {{StraightAction{4.0, 0.5}, {}}, {StraightAction{8.0, 0.5}, {}}}));
  coordinator_.Begin("b", Job("job-b", {{TurnAction{DegToRad(90), 0.3}, {}}}));
  coordinator_.Update();
  ASSERT_EQ(mailbox_.sent["a"].size(), 1u);
  EXPECT_EQ(mailbox_.sent["a"].back().cleared_up_to_action, 0);
  Move("b", Pose2(0, 6, kPi / 2));
  coordinator_.OnActionFinished("b", "job-b", 0);
  coordinator_.End("job-b");
  coordinator_.Update();  // same clock time
  ASSERT_EQ(mailbox_.sent["a"].size(), 2u);
  EXPECT_EQ(mailbox_.sent["a"].back().cleared_up_to_action, 1);
}

TEST_F(TrafficCoordinatorTest, AReconnectedRobotIsSentItsClearanceAgain) {
  Connect("a", Pose2(-8, 0, 0));
  coordinator_.Begin("a", Job("job-a", {{TurnAction{DegToRad(90), 0.3}, {}}}));
  coordinator_.Update();
  ASSERT_EQ(mailbox_.sent["a"].size(), 1u);
  coordinator_.Resend("a");
  coordinator_.Update();
  ASSERT_EQ(mailbox_.sent["a"].size(), 2u);
  EXPECT_EQ(mailbox_.sent["a"].back().cleared_up_to_action, 0);
  EXPECT_EQ(mailbox_.sent["a"].back().job_id, "job-a");
}

// A wide trolley (2.8 m across) on a platform's lift: the platform's own footprint passes 2.6 m
// from the other robot's way, the trolley it carries does not.
const Eigen::Vector2d kWideTrolleyM(1.0, 2.8);

TEST_F(TrafficCoordinatorTest, AParkedRobotCarryingATrolleyBlocksWithTheTrolleysOutline) {
  Connect("a", Pose2(-8, 0, 0));
  Connect("carrier", Pose2(0, 2.6, 0), MecanumPlatformModel());
  coordinator_.Begin("a", Job("job-a1", {{StraightAction{12.0, 0.5}, {}}}));
  coordinator_.Update();
  ASSERT_FALSE(mailbox_.sent["a"].empty());
  EXPECT_EQ(mailbox_.sent["a"].back().cleared_up_to_action, 0);
  coordinator_.End("job-a1");

  // The carrier has picked the trolley up where it stands: the same drive waits for it now.
  Move("carrier", Pose2(0, 2.6, 0), kWideTrolleyM);
  coordinator_.Begin("a", Job("job-a2", {{StraightAction{12.0, 0.5}, {}}}));
  coordinator_.Update();
  EXPECT_EQ(mailbox_.sent["a"].back().cleared_up_to_action, -1);
  EXPECT_THAT(mailbox_.sent["a"].back().wait_reason, HasSubstr("carrier, which stands in its way"));
}

TEST_F(TrafficCoordinatorTest, AJobCarryingATrolleySweepsItsOutlineUntilTheUndock) {
  Connect("idle", Pose2(2, 2.2, 0), MecanumPlatformModel());
  Connect("carrier", Pose2(-8, 0, 0), MecanumPlatformModel());
  Move("carrier", Pose2(-8, 0, 0), kWideTrolleyM);
  coordinator_.Begin("carrier", Job("job-carry", {{StraightAction{12.0, 0.3}, {}}}));
  coordinator_.Update();
  ASSERT_FALSE(mailbox_.sent["carrier"].empty());
  EXPECT_EQ(mailbox_.sent["carrier"].back().cleared_up_to_action, -1);
  EXPECT_THAT(mailbox_.sent["carrier"].back().wait_reason,
              HasSubstr("idle, which stands in its way"));
  coordinator_.End("job-carry");

  // Set down first, the same drive passes.
  coordinator_.Begin("carrier",
                     Job("job-set-down", {{UndockAction{}, {}}, {StraightAction{12.0, 0.3}, {}}}));
  coordinator_.Update();
  EXPECT_EQ(mailbox_.sent["carrier"].back().cleared_up_to_action, 1);
}

}  // namespace
}  // namespace fleetnav::server

namespace fleetnav::server {
namespace {

// A long route is ordered a window of horizon_actions at a time: clearance never runs past the
// predicted window, and the next window is predicted once the robot is half way through this one.
TEST_F(TrafficCoordinatorTest, ALongRouteIsOrderedOneWindowAtATime) {
  Connect("a", Pose2(-14, 0, 0));
  std::vector<RouteAction> actions;
  for (int i = 0; i < 100; ++i) actions.push_back({TurnAction{0.1, 0.3}, {}});
  coordinator_.Begin("a", Job("job-a", actions));
  coordinator_.Update();
  ASSERT_FALSE(mailbox_.sent["a"].empty());
  const int horizon = TrafficCoordinatorParams{}.horizon_actions;
  EXPECT_EQ(mailbox_.sent["a"].back().cleared_up_to_action, horizon - 1);

  // Not yet half way: the window stays.
  coordinator_.OnActionFinished("a", "job-a", horizon / 2 - 2);
  coordinator_.Update();
  EXPECT_EQ(mailbox_.sent["a"].back().cleared_up_to_action, horizon - 1);
  // Half way: the next window is predicted from where the robot is, and cleared.
  coordinator_.OnActionFinished("a", "job-a", horizon / 2 - 1);
  coordinator_.Update();
  EXPECT_EQ(mailbox_.sent["a"].back().cleared_up_to_action, horizon / 2 + horizon - 1);
  // The last window ends with the route.
  for (int finished = horizon / 2; finished < 99; ++finished) {
    coordinator_.OnActionFinished("a", "job-a", finished);
    coordinator_.Update();
  }
  EXPECT_EQ(mailbox_.sent["a"].back().cleared_up_to_action, 99);
}

}  // namespace
}  // namespace fleetnav::server
