#include "fleetnav/localization/samcl_localizer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/localization/sensor_model.hpp"

namespace fleetnav::localization {
namespace {

/// A 10 x 8 m open floor with one feeding fence (0.1 m thick) along y = 1.9 m; base_link
/// starts at the origin, so the left ultrasonic (0.25 m off the axis) sees the fence 1.65 m out.
OccupancyGrid FenceFloor() {
  OccupancyGrid grid = *OccupancyGrid::Filled(200, 160, 0.05, Pose2(-5.0, -4.0, 0.0), 0);
  for (int x = 0; x < grid.width(); ++x) {
    for (int y = 118; y < 120; ++y) grid.SetValue({x, y}, OccupancyGrid::kOccupiedValue);
  }
  return grid;
}

/// An ultrasonic as the simulator and the PIL P42 report it: the nearest echo anywhere in its
/// 10° cone (five rays), nothing beyond 2.5 m.
std::vector<RangeReading> ConeUltrasonics(const OccupancyGrid& map, const RobotModel& model,
                                          const Pose2& pose_in_map) {
  constexpr double kRangeMaxM = 2.5;
  std::vector<RangeReading> readings;
  for (const SensorMount& mount : model.sensors) {
    if (mount.type != SensorType::kUltrasonic) continue;
    const Pose2 sensor = pose_in_map * mount.pose_in_base;
    double nearest = kRangeMaxM;
    for (int i = 0; i < 5; ++i) {
      const double angle = sensor.yaw_rad() + DegToRad(-5.0 + 2.5 * i);
      nearest = std::min(nearest, CastRay(map, sensor.translation(), angle, kRangeMaxM));
    }
    readings.push_back({mount.name, nearest, nearest < kRangeMaxM});
  }
  return readings;
}

/// A constant command the robot follows for a while.
struct Motion {
  double speed_mps = 0.0;
  double yaw_rate_radps = 0.0;
  double duration_s = 0.0;
};

/// Drives the Lely from `start` through `motions` (50 Hz frames: exact encoder ticks and gyro,
/// ultrasonics that see `world`) while its localizer knows only `map`, and returns the largest
/// distance of the estimate from the true pose.
double LargestErrorAlong(const SamclLocalizerParams& params, const OccupancyGrid& world,
                         const OccupancyGrid& map, const Pose2& start,
                         const std::vector<Motion>& motions) {
  const RobotModel model = LelyVectorModel();
  absl::StatusOr<SamclLocalizer> localizer =
      SamclLocalizer::Create(model, map, MarkerSet{}, start, params);
  EXPECT_TRUE(localizer.ok()) << localizer.status();
  if (!localizer.ok()) return 1e9;
  constexpr double kTickS = 0.02;
  const double ticks_per_m = model.encoder_ticks_per_rev / (2.0 * kPi * model.wheel_radius_m);
  Pose2 truth = start;
  double left_m = 0.0;
  double right_m = 0.0;
  double error_m = 0.0;
  uint64_t tick = 0;
  double yaw_rate_radps = 0.0;
  auto frame_now = [&] {
    SensorFrame frame;
    frame.tick = tick;
    frame.stamp_ns = static_cast<int64_t>(tick) * 20'000'000;
    frame.control_period_s = kTickS;
    frame.encoders = {{"left", std::llround(left_m * ticks_per_m)},
                      {"right", std::llround(right_m * ticks_per_m)}};
    frame.imu.gyro_z_radps = yaw_rate_radps;
    frame.ultrasonic = ConeUltrasonics(world, model, truth);
    EXPECT_TRUE(localizer->Update(frame).ok());
    error_m = std::max(
        error_m, (localizer->estimate().pose_in_map.translation() - truth.translation()).norm());
  };
  frame_now();
  for (const Motion& motion : motions) {
    const int ticks = static_cast<int>(std::lround(motion.duration_s / kTickS));
    for (int k = 0; k < ticks; ++k) {
      yaw_rate_radps = motion.yaw_rate_radps;
      const double forward_m = motion.speed_mps * kTickS;
      const double turn_m = 0.5 * model.track_m * motion.yaw_rate_radps * kTickS;
      left_m += forward_m - turn_m;
      right_m += forward_m + turn_m;
      const double mid_yaw = truth.yaw_rad() + 0.5 * motion.yaw_rate_radps * kTickS;
      truth = Pose2(truth.x_m() + forward_m * std::cos(mid_yaw),
                    truth.y_m() + forward_m * std::sin(mid_yaw),
                    truth.yaw_rad() + motion.yaw_rate_radps * kTickS);
      ++tick;
      frame_now();
    }
  }
  return error_m;
}

/// Turns the Lely in place at the origin twice round at 0.3 rad/s and returns the largest
/// distance of the estimate from the place it never left.
double DriftOfTwoTurnsInPlace(const SamclLocalizerParams& params) {
  const OccupancyGrid fence = FenceFloor();
  return LargestErrorAlong(params, fence, fence, Pose2(), {{0.0, 0.3, 4.0 * kPi / 0.3}});
}

TEST(SamclLocalizerTest, ATurnInPlaceBesideAFenceLeavesTheEstimateWhereTheRobotIs) {
  // The ultrasonics report the nearest echo in their cone; weighed by the beam model over the
  // same cone, two turns in place leave the estimate within a few centimetres.
  SamclLocalizerParams params;
  params.amcl.seed = 7;
  const double beam_drift_m = DriftOfTwoTurnsInPlace(params);
  EXPECT_LT(beam_drift_m, 0.04);
  // The axis-only likelihood field reads every oblique echo short and pulls the estimate
  // towards the fence (generated barn 1025's free leg ended 0.15 m off its goal so).
  params.ultrasonic_sensor_model = SensorModelType::kLikelihoodField;
  params.ultrasonic_cone_rad = 0.0;
  const double axis_drift_m = DriftOfTwoTurnsInPlace(params);
  EXPECT_GT(axis_drift_m, 2.0 * beam_drift_m);
  EXPECT_GT(axis_drift_m, 0.06);
}

TEST(SamclLocalizerTest, RefusesABadUltrasonicBeamModel) {
  SamclLocalizerParams params;
  params.ultrasonic_beam.sigma_hit_m = -1.0;
  const absl::Status s = params.Validate();
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("ultrasonic_beam"), std::string::npos) << s;
}

}  // namespace
}  // namespace fleetnav::localization
