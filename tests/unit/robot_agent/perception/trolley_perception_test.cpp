// The trolley perception pipeline on generated scans with known answers (KUKA thesis ch.
// 12-15): filters, clustering, iterative end-point fit, circle extraction, trolley recognition
// and dock frames.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/robot_agent/control/modes/move_controller.hpp"
#include "fleetnav/robot_agent/control/modes/trolley_docking_controller.hpp"
#include "fleetnav/robot_agent/laser_filters.hpp"
#include "fleetnav/robot_agent/scan_features.hpp"
#include "fleetnav/robot_agent/trolley_recognition.hpp"
#include "kinematic_unicycle.hpp"

namespace fleetnav::agent {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// A 270° scan at 0.5° from the origin of a world of circles (legs) and a wall at x = wall_x_m
/// (kInf: none), with Gaussian range noise.
LaserScanSample Scan(const std::vector<Eigen::Vector2d>& legs, double leg_radius_m, double wall_x_m,
                     double noise_m, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_m > 0 ? noise_m : 1.0);
  LaserScanSample scan;
  scan.name = "laser";
  scan.angle_min_rad = -135.0 * kPi / 180.0;
  scan.angle_increment_rad = 0.5 * kPi / 180.0;
  scan.range_max_m = 20.0;
  for (int i = 0; i < 541; ++i) {
    const double a = scan.angle_min_rad + i * scan.angle_increment_rad;
    const Eigen::Vector2d d(std::cos(a), std::sin(a));
    double best = kInf;
    if (std::isfinite(wall_x_m) && d.x() > 1e-9) best = wall_x_m / d.x();
    for (const Eigen::Vector2d& c : legs) {
      const double along = c.dot(d);
      const double miss2 = c.squaredNorm() - along * along;
      if (along > 0 && miss2 < leg_radius_m * leg_radius_m) {
        best = std::min(best, along - std::sqrt(leg_radius_m * leg_radius_m - miss2));
      }
    }
    const double r = std::isfinite(best) ? best + (noise_m > 0 ? noise(rng) : 0.0) : 25.0;
    scan.ranges_m.push_back(static_cast<float>(r));
  }
  return scan;
}

/// The four leg centres of a trolley (spec spacings) at `pose`.
std::vector<Eigen::Vector2d> Legs(const Pose2& pose, const TrolleySpec& spec) {
  std::vector<Eigen::Vector2d> legs;
  for (double sx : {-0.5, 0.5}) {
    for (double sy : {-0.5, 0.5}) {
      legs.push_back(pose.TransformPoint({sx * spec.leg_spacing_x_m, sy * spec.leg_spacing_y_m}));
    }
  }
  return legs;
}

TEST(LaserFiltersTest, TemporalMedianKeepsAThinLegAndDropsAnOutlier) {
  TemporalMedianFilter median(3);
  LaserScanSample scan;
  scan.ranges_m = {5.0f, 2.0f, 5.0f};  // one beam on a leg
  median.Apply(scan);
  scan.ranges_m = {5.0f, 2.0f, 0.3f};  // a spurious short return on beam 2
  median.Apply(scan);
  scan.ranges_m = {5.0f, 2.0f, 5.0f};
  const LaserScanSample out = median.Apply(scan);
  EXPECT_FLOAT_EQ(out.ranges_m[1], 2.0f);  // a spatial median would have erased it
  EXPECT_FLOAT_EQ(out.ranges_m[2], 5.0f);
}

TEST(LaserFiltersTest, ShadowFilterDropsTheVeilBehindAnEdgeNotTheEdge) {
  LaserScanSample scan;
  scan.angle_increment_rad = 0.5 * kPi / 180.0;
  scan.range_max_m = 20.0;
  // A leg at 1 m, then points trailing from it to a wall at 4 m: the 2 and 3 m returns lie
  // almost along their beams (veiling).
  scan.ranges_m = {1.0f, 1.0f, 2.0f, 3.0f, 4.0f, 4.0f};
  const LaserScanSample out = RemoveShadows(scan, ShadowFilterParams{});
  EXPECT_FLOAT_EQ(out.ranges_m[0], 1.0f);
  EXPECT_FLOAT_EQ(out.ranges_m[1], 1.0f);
  EXPECT_TRUE(std::isinf(out.ranges_m[2]));
  EXPECT_TRUE(std::isinf(out.ranges_m[3]));
}

TEST(ScanFeaturesTest, ClustersLinesAndCircles) {
  const Pose2 laser;
  const LaserScanSample scan = Scan({{1.5, 0.5}}, 0.02, 3.0, 0.0, 1);
  const std::vector<std::vector<Eigen::Vector2d>> clusters =
      ClusterPoints(ScanPoints(scan, laser), 0.06);
  // The leg is a cluster of its own, of a few points, and fits a circle at its centre.
  size_t leg = clusters.size(), wall = 0;
  for (size_t i = 0; i < clusters.size(); ++i) {
    if ((clusters[i].front() - Eigen::Vector2d(1.5, 0.5)).norm() < 0.05) leg = i;
    if (clusters[i].size() > clusters[wall].size()) wall = i;
  }
  ASSERT_LT(leg, clusters.size());
  EXPECT_LE(clusters[leg].size(), 4u);
  const std::optional<Circle> circle = FitCircleOfRadius(clusters[leg], 0.02, laser.translation());
  ASSERT_TRUE(circle.has_value());
  EXPECT_NEAR((circle->center_m - Eigen::Vector2d(1.5, 0.5)).norm(), 0.0, 0.003);
  // The longest piece of wall is straight: one segment along x = 3.
  const std::vector<LineSegment> lines =
      IterativeEndPointFit(clusters[wall], 0.01, 5.0 * kPi / 180.0);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_NEAR(lines[0].from.x(), 3.0, 1e-6);
  EXPECT_NEAR(lines[0].to.x(), 3.0, 1e-6);
  EXPECT_GT(lines[0].length_m(), 1.0);
  // A corner splits into two segments at the corner point.
  std::vector<Eigen::Vector2d> corner;
  for (int i = 0; i <= 10; ++i) corner.emplace_back(0.1 * i, 0.0);
  for (int i = 1; i <= 10; ++i) corner.emplace_back(1.0, 0.1 * i);
  const std::vector<LineSegment> pieces = IterativeEndPointFit(corner, 0.01, 0.1);
  ASSERT_EQ(pieces.size(), 2u);
  EXPECT_NEAR((pieces[0].to - Eigen::Vector2d(1.0, 0.0)).norm(), 0.0, 1e-9);
}

TEST(TrolleyRecognitionTest, FindsTheTrolleyAndItsDockFramesInANoisyScan) {
  const TrolleySpec spec;
  int found = 0;
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    // A trolley 1.8-2.6 m ahead, up to ±0.5 m aside, turned up to ±30°, a shelf behind it.
    const Pose2 trolley(2.2 + 0.4 * u(rng), 0.5 * u(rng), 0.52 * u(rng));
    const LaserScanSample scan = Scan(Legs(trolley, spec), spec.leg_radius_m, 4.5, 0.01, seed);
    const std::vector<TrolleyDetection> trolleys =
        RecognizeTrolleys(LegCandidates(scan, Pose2(), spec), spec);
    if (trolleys.empty()) continue;
    ++found;
    const Pose2& seen = trolleys.front().pose_in_base;
    EXPECT_NEAR((seen.translation() - trolley.translation()).norm(), 0.0, 0.025) << seed;
    EXPECT_NEAR(std::remainder(seen.yaw_rad() - trolley.yaw_rad(), 2 * kPi), 0.0, 0.05) << seed;
    EXPECT_GE(trolleys.front().legs_seen, 3) << seed;  // one leg may hide behind another
  }
  EXPECT_GE(found, 19);
  // Legs of the wrong spacing are no trolley.
  TrolleySpec other = spec;
  other.leg_spacing_x_m = 0.6;
  EXPECT_TRUE(RecognizeTrolleys(Legs(Pose2(2, 0, 0), other), spec).empty());

  // Dock frames: the approach frame in front of the near end, facing along x; the final frame
  // at the centre.
  const RobotModel model = MecanumPlatformModel();
  const DockFrames frames = DockFramesFor(Pose2(2, 1, (kPi / 2)), spec, model, 0.25);
  EXPECT_NEAR(frames.final.x_m(), 2.0, 1e-9);
  EXPECT_NEAR(frames.final.y_m(), 1.0, 1e-9);
  EXPECT_NEAR(frames.approach.x_m(), 2.0, 1e-9);
  EXPECT_NEAR(frames.approach.y_m(), 1.0 - (0.48 + 0.02 + 0.394 + 0.25), 1e-9);
  EXPECT_NEAR(frames.approach.yaw_rad(), (kPi / 2), 1e-9);
}

TEST(TrolleyRecognitionTest, APlatformUnderATrolleyLeavesThroughTheMiddleOfTheLegsAhead) {
  // Just set down, the trolley stands up to 6 cm and 5° off the platform's centre; the laser
  // (0.35 m ahead of the centre, 270°) sees the two legs ahead a third of a metre away.
  const TrolleySpec spec;
  const Pose2 laser_in_base(0.35, 0.0, 0.0);
  int found = 0;
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const Pose2 trolley(0.06 * u(rng), 0.06 * u(rng), 0.087 * u(rng));
    std::vector<Eigen::Vector2d> in_laser;
    for (const Eigen::Vector2d& leg : Legs(trolley, spec)) {
      in_laser.push_back(laser_in_base.Inverse().TransformPoint(leg));
    }
    // The median of three scans, as the move takes them standing.
    TemporalMedianFilter median(3);
    LaserScanSample scan;
    for (uint64_t k = 0; k < 3; ++k) {
      scan = median.Apply(Scan(in_laser, spec.leg_radius_m, kInf, 0.01, 100 * seed + k));
    }
    const std::optional<LegGate> gate =
        FindLegGate(LegsAround(scan, laser_in_base, spec), Eigen::Vector2d(1.0, 0.0), spec, 0.2,
                    20.0 * kPi / 180.0);

    if (!gate) continue;
    ++found;
    const Eigen::Vector2d middle = trolley.TransformPoint({0.5 * spec.leg_spacing_x_m, 0.0});
    EXPECT_NEAR((gate->middle_m - middle).norm(), 0.0, 0.02) << seed;
    EXPECT_NEAR(std::atan2(gate->direction.y(), gate->direction.x()), trolley.yaw_rad(), 0.035)
        << seed;
    // Backwards there is no gate in view (the legs behind are outside the laser's 270°).
    EXPECT_FALSE(FindLegGate(LegsAround(scan, laser_in_base, spec), Eigen::Vector2d(-1.0, 0.0),
                             spec, 0.2, 20.0 * kPi / 180.0));
  }
  EXPECT_EQ(found, 20);
  // Two legs of the wrong spacing are no gate; nor is a gate far off the move's line.
  EXPECT_FALSE(FindLegGate({{0.5, -0.2}, {0.5, 0.2}}, {1.0, 0.0}, spec, 0.2, 0.35));
  EXPECT_FALSE(FindLegGate({{0.5, 0.0}, {0.5, 0.66}}, {1.0, 0.0}, spec, 0.2, 0.35));
}

TEST(TrolleyLeavingTest, AMoveFromUnderATrolleyPassesBetweenItsLegsOnTheirMiddleLine) {
  // The trolley set down 5 cm left of the platform's centre and 4° turned: moving straight out
  // by its own heading the platform would pass 0.07 m off the legs' middle (0.09 m a side).
  const TrolleySpec spec;
  const Pose2 laser_in_base(0.35, 0.0, 0.0);
  const Pose2 trolley(0.0, 0.05, 0.07);
  std::vector<Eigen::Vector2d> in_laser;
  for (const Eigen::Vector2d& leg : Legs(trolley, spec)) {
    in_laser.push_back(laser_in_base.Inverse().TransformPoint(leg));
  }
  MoveController controller(MoveAction{1.3, 0.0, 0.15}, std::nullopt, MecanumPlatformModel(),
                            MoveParams{}, spec);
  constexpr double kDtS = 0.02;
  Pose2 pose;
  std::optional<Pose2> at_legs;  // the platform's pose in the trolley's frame at the legs' line
  for (int tick = 0; tick < 5000; ++tick) {
    ControlInput input;
    input.pose_in_map = pose;
    input.pose_in_odom = pose;
    input.dt_s = kDtS;
    input.perception.laser_in_base = laser_in_base;
    if (tick % 5 == 0) input.perception.laser = Scan(in_laser, spec.leg_radius_m, kInf, 0.01, tick);
    const ControlOutput out = controller.Step(input);
    ASSERT_TRUE(out.failure.ok()) << out.failure;
    if (out.done) break;
    pose = testing::MovedOmni(pose, out.command, kDtS);
    const Pose2 in_trolley = trolley.Inverse() * pose;
    if (!at_legs && in_trolley.x_m() >= 0.5 * spec.leg_spacing_x_m) at_legs = in_trolley;
  }
  ASSERT_TRUE(at_legs.has_value());
  EXPECT_NEAR(at_legs->y_m(), 0.0, 0.01);
  EXPECT_NEAR(at_legs->yaw_rad(), 0.0, 0.02);
}

// A spurious leg 0.96 m in front of the trolley's near legs makes a three-leg look-alike with
// them, nearer the robot and within the metre the site's expectation allows. The platform
// docks under the trolley the site expects, all of whose four legs it sees: it drives (perfect
// odometry, kinematic) to the trolley's centre, not to the look-alike's.
TEST(TrolleyDockingControllerTest, DocksUnderTheTrolleyNotAThreeLegLookAlike) {
  const TrolleySpec spec;
  const Pose2 trolley(3.0, 0.0, 0.0);
  std::vector<Eigen::Vector2d> world_legs = Legs(trolley, spec);
  world_legs.push_back(
      trolley.TransformPoint({-1.5 * spec.leg_spacing_x_m, 0.5 * spec.leg_spacing_y_m}));
  TrolleyDockingParams params;
  params.spec = spec;
  TrolleyDockingController controller(MecanumPlatformModel(), params, "t1", trolley);
  Pose2 robot;
  double furthest_x_m = 0.0;
  for (int step = 0; step < 1500; ++step) {
    ControlInput input;
    input.dt_s = 0.05;
    input.pose_in_odom = robot;
    input.pose_in_map = robot;
    std::vector<Eigen::Vector2d> legs_in_base;
    for (const Eigen::Vector2d& leg : world_legs) {
      legs_in_base.push_back(robot.Inverse().TransformPoint(leg));
    }
    input.perception.laser = Scan(legs_in_base, spec.leg_radius_m, kInf, 0.0, 1);
    const ControlOutput out = controller.Step(input);
    ASSERT_TRUE(out.failure.ok()) << out.failure;
    if (out.lift_raised) break;  // at the final frame
    robot = robot * Pose2(out.command.vx_mps * input.dt_s, out.command.vy_mps * input.dt_s,
                          out.command.yaw_rate_radps * input.dt_s);
    furthest_x_m = std::max(furthest_x_m, robot.x_m());
  }
  EXPECT_TRUE(robot.IsNear(trolley, 0.01, 0.02)) << robot.DebugString();
  EXPECT_LT(furthest_x_m, trolley.x_m() + 0.02);
}

}  // namespace
}  // namespace fleetnav::agent
