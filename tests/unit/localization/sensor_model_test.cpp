#include "fleetnav/localization/sensor_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/localization/amcl.hpp"
#include "fleetnav/localization/samcl.hpp"
#include "fleetnav/localization/synthetic.hpp"

namespace fleetnav::localization {
namespace {

OccupancyGrid Barn() { return *SyntheticBarnMap(0.05); }

TEST(LikelihoodFieldTest, DistanceIsExactAndOutsideIsFloor) {
  const OccupancyGrid map = Barn();
  const LikelihoodField field = *LikelihoodField::Create(map, LikelihoodFieldParams{});
  // The north fence occupies y in [5.85, 5.90]; 0.5 m below it the distance is ~0.5 m.
  EXPECT_NEAR(field.DistanceM(0.0f, 5.4f), 0.45f, 0.06f);
  EXPECT_NEAR(field.DistanceM(0.0f, 5.87f), 0.0f, 1e-6f);
  EXPECT_LT(field.LogHit(100.0f, 0.0f), field.LogHit(0.0f, 5.87f));
  EXPECT_FLOAT_EQ(field.LogHit(0.0f, 5.87f), field.max_log_hit());
}

// The agent's field: end points within 5 cm (DefaultAgentAmclParams).
LikelihoodFieldParams AgentFieldParams() {
  LikelihoodFieldParams p;
  p.sigma_hit_m = 0.05;
  return p;
}

// A 6 x 4 m floor at 5 cm with a solid box over x in [3, 4] m (a feed kitchen, a shelf).
OccupancyGrid FloorWithSolidBox() {
  OccupancyGrid grid = *OccupancyGrid::Filled(120, 80, 0.05, Pose2(), 0);
  for (int y = 0; y < 80; ++y) {
    for (int x = 60; x < 80; ++x) grid.SetValue(CellIndex{x, y}, OccupancyGrid::kOccupiedValue);
  }
  return grid;
}

TEST(LikelihoodFieldTest, AnEndPointInsideASolidBoxIsAsFarFromAnEchoAsOneInFrontOfIt) {
  const LikelihoodField field = *LikelihoodField::Create(FloorWithSolidBox(), AgentFieldParams());
  // The faces are surfaces; the middle of the box is half a metre from either.
  EXPECT_NEAR(field.DistanceM(3.01f, 2.0f), 0.0f, 1e-6f);
  EXPECT_NEAR(field.DistanceM(3.99f, 2.0f), 0.0f, 1e-6f);
  EXPECT_NEAR(field.DistanceM(3.5f, 2.0f), 0.475f, 0.03f);
  // Three cells inside the face score as badly as three cells in front of it.
  EXPECT_FLOAT_EQ(field.LogHit(3.175f, 2.0f), field.LogHit(2.875f, 2.0f));
  EXPECT_LT(field.LogHit(3.175f, 2.0f), field.max_log_hit() - 3.0f);
}

TEST(LikelihoodFieldTest, AConeBeamFitsAnEchoFromOffItsAxis) {
  // An ultrasonic 2.5 m from the box's face, its axis 25 degrees off the face's normal: the
  // nearest surface in its 10 degree cone is 20 degrees off, 2.5 / cos 20 = 2.66 m away.
  const LikelihoodField field = *LikelihoodField::Create(FloorWithSolidBox(), AgentFieldParams());
  const double reading_m = 2.5 / std::cos(DegToRad(20.0));
  RangeBeam beam{{0.0, 0.0}, DegToRad(25.0), reading_m, 4.0, false};
  RangeObservation ray;
  ray.beams.push_back(beam);
  beam.cone_rad = DegToRad(10.0);
  RangeObservation cone;
  cone.beams.push_back(beam);
  float x = 0.5f, y = 1.0f, yaw = 0.0f;
  float ll_ray = 0.0f, ll_cone = 0.0f;
  field.Accumulate(ray, &x, &y, &yaw, 1, &ll_ray);
  field.Accumulate(cone, &x, &y, &yaw, 1, &ll_cone);
  EXPECT_NEAR(ll_cone, field.max_log_hit(), 0.1f);  // the truth fits the cone's reading
  EXPECT_LT(ll_ray, ll_cone - 1.0f);                // on the axis alone it reads 9 cm short
  const std::vector<double> angles = BeamRayAngles(beam);
  ASSERT_EQ(angles.size(), 11u);
  EXPECT_NEAR(angles.front(), DegToRad(20.0), 1e-12);
  EXPECT_NEAR(angles.back(), DegToRad(30.0), 1e-12);
  beam.cone_rad = 0.0;
  EXPECT_EQ(BeamRayAngles(beam), std::vector<double>{DegToRad(25.0)});
}

TEST(LikelihoodFieldTest, RejectsBadParamsAndRotatedMaps) {
  LikelihoodFieldParams p;
  p.sigma_hit_m = -1.0;
  EXPECT_EQ(LikelihoodField::Create(Barn(), p).status().code(), absl::StatusCode::kInvalidArgument);
  const OccupancyGrid rotated = *OccupancyGrid::Filled(10, 10, 0.1, Pose2(0, 0, 0.3), 0);
  EXPECT_EQ(LikelihoodField::Create(rotated, LikelihoodFieldParams{}).status().code(),
            absl::StatusCode::kInvalidArgument);
}

TEST(LikelihoodFieldTest, TruePoseScoresBestAndNoEchoIsEvidence) {
  const OccupancyGrid map = Barn();
  const LikelihoodField field = *LikelihoodField::Create(map, LikelihoodFieldParams{});
  Rng rng(5);
  const Pose2 truth(-4.0, 2.5, 0.3);
  const RangeObservation scan = SimulateLaser(map, truth, 60, 12.0, 0.01, rng);
  float x[3] = {-4.0f, -3.7f, -4.0f};
  float y[3] = {2.5f, 2.5f, 2.5f};
  float yaw[3] = {0.3f, 0.3f, 0.5f};
  float ll[3] = {0, 0, 0};
  field.Accumulate(scan, x, y, yaw, 3, ll);
  EXPECT_GT(ll[0], ll[1]);
  EXPECT_GT(ll[0], ll[2]);
  // A no-echo ultrasonic: a pose whose beam would pass by the fence is less likely.
  RangeObservation no_echo;
  no_echo.beams.push_back(RangeBeam{{0.0, 0.0}, kPi / 2.0, 2.0, 2.0, true});
  float nx[2] = {0.0f, 0.0f};
  float ny[2] = {2.0f, 4.7f};  // fence 3.9 m away vs 1.2 m away
  float nyaw[2] = {0.0f, 0.0f};
  float nll[2] = {0, 0};
  field.Accumulate(no_echo, nx, ny, nyaw, 2, nll);
  EXPECT_GT(nll[0], nll[1] + 1.0f);
}

TEST(BeamModelTest, RayCastAndLikelihood) {
  const OccupancyGrid map = Barn();
  EXPECT_NEAR(CastRay(map, {0.0, 4.7}, kPi / 2.0, 5.0), 1.15, 0.06);
  EXPECT_DOUBLE_EQ(CastRay(map, {0.0, 4.7}, -kPi / 2.0, 3.0), 3.0);
  const BeamModel model(map, BeamModelParams{});
  EXPECT_GT(model.LogLikelihood(1.0, 1.0, 5.0, false), model.LogLikelihood(1.5, 1.0, 5.0, false));
  EXPECT_GT(model.LogLikelihood(5.0, 5.0, 5.0, true), model.LogLikelihood(5.0, 1.0, 5.0, true));
  float x = 0.0f, y = 4.7f, yaw = 0.0f, ll = 0.0f;
  RangeObservation obs;
  obs.beams.push_back(RangeBeam{{0.0, 0.0}, kPi / 2.0, 1.15, 5.0, false});
  EXPECT_EQ(model.Accumulate(obs, &x, &y, &yaw, 1, &ll), 1);
  EXPECT_GT(ll, 0.0f);
}

TEST(FakeLaserTest, KeepsNoEchoBeams) {
  const RobotModel model = LelyVectorModel();
  std::vector<RangeReading> readings = {{"ultrasonic_left", 0.9, true},
                                        {"ultrasonic_right", 2.5, false}};
  const RangeObservation obs = *FakeLaserFromUltrasonics(readings, model, 2.5);
  ASSERT_EQ(obs.beams.size(), 2u);
  EXPECT_FALSE(obs.beams[0].no_echo);
  EXPECT_TRUE(obs.beams[1].no_echo);
  EXPECT_NEAR(obs.beams[0].angle_in_base_rad, kPi / 2.0, 1e-12);
  const RangeObservation coned = *FakeLaserFromUltrasonics(readings, model, 2.5, DegToRad(10.0));
  EXPECT_NEAR(coned.beams[0].cone_rad, DegToRad(10.0), 1e-12);
  EXPECT_EQ(FakeLaserFromUltrasonics(readings, model, 2.5, -0.1).status().code(),
            absl::StatusCode::kInvalidArgument);
  readings.push_back({"nope", 1.0, true});
  EXPECT_EQ(FakeLaserFromUltrasonics(readings, model, 2.5).status().code(),
            absl::StatusCode::kInvalidArgument);
}

TEST(AmclTest, ValidatesAndRequiresInitialisation) {
  AmclParams bad;
  bad.max_particles = 10;
  bad.min_particles = 20;
  EXPECT_EQ(Amcl::Create(bad, Barn()).status().code(), absl::StatusCode::kInvalidArgument);
  Amcl amcl = *Amcl::Create(AmclParams{}, Barn());
  EXPECT_EQ(amcl.Update(Pose2(), RangeObservation{}, 0).status().code(),
            absl::StatusCode::kFailedPrecondition);
}

TEST(AmclTest, GateSkipsSmallMotionButRefinesWhenStationary) {
  AmclParams params;
  params.min_particles = params.max_particles = 300;
  Amcl amcl = *Amcl::Create(params, Barn());
  ASSERT_TRUE(amcl.InitializePose(Pose2(-4, 2.5, 0), {0.1, 0.1, 0.05}, Pose2(), 0).ok());
  Rng rng(1);
  const OccupancyGrid map = Barn();
  const RangeObservation scan = SimulateLaser(map, Pose2(-4, 2.5, 0), 30, 12.0, 0.01, rng);
  EXPECT_TRUE(*amcl.Update(Pose2(), scan, 0));  // first update always runs
  EXPECT_FALSE(*amcl.Update(Pose2(0.01, 0, 0), scan, 100'000'000));
  EXPECT_TRUE(*amcl.Update(Pose2(0.2, 0, 0), scan, 200'000'000));
  // At rest: one refinement per stationary period.
  EXPECT_FALSE(*amcl.Update(Pose2(0.2, 0, 0), scan, 500'000'000));
  EXPECT_TRUE(*amcl.Update(Pose2(0.2, 0, 0), scan, 1'300'000'000));
  // map → odom composes with odom to the estimate.
  const Pose2 in_map = amcl.PoseInMap(amcl.filter_pose_in_odom());
  EXPECT_TRUE(in_map.IsNear(amcl.estimate().pose_in_map, 1e-6, 1e-6));
  EXPECT_FALSE(amcl.health().lost);
  EXPECT_GT(amcl.health().confidence, 0.3);
}

TEST(SamclTest, HardCalibrationPutsSensorPointsOnTheMarker) {
  const OccupancyGrid map = Barn();
  const RobotModel model = LelyVectorModel();
  AmclParams params;
  params.min_particles = params.max_particles = 200;
  Amcl amcl = *Amcl::Create(params, map);
  // The estimate is 0.3 m behind; the inductive sensor is really on the marker at x = 0.
  const Pose2 sensor = model.FindSensor("inductive_left")->pose_in_base;
  const Pose2 truth(-sensor.x_m(), 4.7, 0.0);
  ASSERT_TRUE(
      amcl.InitializePose(Pose2(truth.x_m() - 0.3, 4.7, 0), {0.2, 0.02, 0.01}, Pose2(), 0).ok());
  Samcl samcl = *Samcl::Create(std::move(amcl), Experiment2Markers(), model, SamclParams{});
  samcl.RecordOdometry(Pose2(), 0);
  samcl.RecordOdometry(Pose2(0.1, 0, 0), 1'000'000'000);
  // Edge half way: the robot (odometry) moved 0.05 m after it.
  const CalibrationResult r = *samcl.OnInductiveEdge({"inductive_left", 500'000'000});
  EXPECT_EQ(r.outcome, CalibrationOutcome::kApplied);
  EXPECT_EQ(r.marker_id, 1);
  const Pose2 estimate = samcl.amcl().estimate().pose_in_map;
  // At the edge the sensor was at x = 0; now the robot is 0.05 m further.
  EXPECT_NEAR(estimate.x_m(), truth.x_m() + 0.05, 0.01);
  EXPECT_NEAR(estimate.y_m(), 4.7, 0.01);
  EXPECT_EQ(samcl.OnInductiveEdge({"ultrasonic_left", 0}).status().code(),
            absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(samcl.OnInductiveEdge({"inductive_left", 5'000'000'000}).status().code(),
            absl::StatusCode::kOutOfRange);
}

TEST(SamclTest, RefusesAmbiguousAndFarMarkers) {
  const OccupancyGrid map = Barn();
  const RobotModel model = LelyVectorModel();
  AmclParams params;
  params.min_particles = params.max_particles = 100;
  Amcl amcl = *Amcl::Create(params, map);
  ASSERT_TRUE(amcl.InitializePose(Pose2(-0.8, 4.7, 0), {0.05, 0.05, 0.01}, Pose2(), 0).ok());
  MarkerSet markers = Experiment2Markers();
  StripeMarker close = markers.markers[0];
  close.id = 9;
  close.position_m = {-0.3, 4.7};
  markers.markers.push_back(close);
  Samcl samcl = *Samcl::Create(std::move(amcl), markers, model, SamclParams{});
  samcl.RecordOdometry(Pose2(), 0);
  samcl.RecordOdometry(Pose2(0.1, 0, 0), 100);
  // The sensor point (x ≈ −0.31) is within h of both markers at 0 and −0.3.
  const CalibrationResult r = *samcl.OnInductiveEdge({"inductive_left", 50});
  EXPECT_EQ(r.outcome, CalibrationOutcome::kAmbiguous);
  SamclParams narrow;
  narrow.association_radius_m = 0.01;
  Amcl amcl2 = *Amcl::Create(params, map);
  ASSERT_TRUE(amcl2.InitializePose(Pose2(-0.8, 4.7, 0), {0.05, 0.05, 0.01}, Pose2(), 0).ok());
  Samcl far = *Samcl::Create(std::move(amcl2), markers, model, narrow);
  far.RecordOdometry(Pose2(), 0);
  EXPECT_EQ(far.OnInductiveEdge({"inductive_left", 0})->outcome, CalibrationOutcome::kNoMarker);
}

}  // namespace
}  // namespace fleetnav::localization

namespace fleetnav::localization {
namespace {

/// Experiment 2's markers (marker 1 across the lane at x = 0) and one follow stripe piece.
MarkerSet MarkersWithStripe(const Eigen::Vector2d& centre_m, double yaw_rad, double length_m) {
  MarkerSet markers = Experiment2Markers();
  StripeMarker stripe;
  stripe.id = 7;
  stripe.kind = MarkerKind::kFollowStripe;
  stripe.stripe_id = 1;
  stripe.position_m = centre_m;
  stripe.yaw_rad = NormalizeMarkerYaw(yaw_rad);
  stripe.length_m = length_m;
  markers.markers.push_back(stripe);
  return markers;
}

/// SAMCL over `markers` for a robot heading east along y = 4.7 whose estimate is at
/// estimate_x_m with `stddev`, odometry starting at the origin at stamp 0.
Samcl SamclAt(const MarkerSet& markers, double estimate_x_m, const Eigen::Vector3d& stddev) {
  AmclParams params;
  params.min_particles = params.max_particles = 500;
  Amcl amcl = *Amcl::Create(params, Barn());
  EXPECT_TRUE(amcl.InitializePose(Pose2(estimate_x_m, 4.7, 0), stddev, Pose2(), 0).ok());
  Samcl samcl = *Samcl::Create(std::move(amcl), markers, LelyVectorModel(), SamclParams{});
  samcl.RecordOdometry(Pose2(), 0);
  return samcl;
}

Eigen::Vector2d LeftInductiveInBase() {
  return LelyVectorModel().FindSensor("inductive_left")->pose_in_base.translation();
}

// The farm robot's failure on unseen barns: driving to a marker it first crosses the end of a
// stripe 0.47 m before it. Whether the estimate is right or 0.4 m off along the track (normal
// after a leg driven by distance), the stripe's edge calibrates nothing and the marker's does.
TEST(SamclTest, AStripeEndCrossedJustBeforeAMarkerIsNotTakenForIt) {
  const Eigen::Vector2d sensor = LeftInductiveInBase();
  constexpr double kGapM = 0.47;
  // Across the lane, from just below the sensor's line northwards.
  const MarkerSet markers =
      MarkersWithStripe({-kGapM, 4.7 + sensor.y() - 0.05 + 1.0}, kPi / 2.0, 2.0);
  for (const double along_error_m : {0.0, 0.4, -0.4}) {
    SCOPED_TRACE(along_error_m);
    // The sensor is on the stripe's end; the estimate along_error_m ahead of the truth.
    const double truth_x_m = -kGapM - sensor.x();
    Samcl samcl = SamclAt(markers, truth_x_m + along_error_m, {0.25, 0.02, 0.005});
    const CalibrationResult at_stripe = *samcl.OnInductiveEdge({"inductive_left", 0});
    EXPECT_NE(at_stripe.outcome, CalibrationOutcome::kApplied);
    EXPECT_NEAR(samcl.amcl().estimate().pose_in_map.x_m(), truth_x_m + along_error_m, 0.06);
    // 0.47 m further the sensor crosses the marker.
    samcl.RecordOdometry(Pose2(kGapM, 0, 0), 1'000'000'000);
    const CalibrationResult at_marker = *samcl.OnInductiveEdge({"inductive_left", 1'000'000'000});
    EXPECT_EQ(at_marker.outcome, CalibrationOutcome::kApplied);
    EXPECT_EQ(at_marker.marker_id, 1);
    EXPECT_NEAR(samcl.amcl().estimate().pose_in_map.x_m(), truth_x_m + kGapM, 0.03);
  }
}

// Generated barn 1152 with the error cases: driving to marker 2 the left sensor crossed the
// return stripes' row and, 0.74 m later, the end of stripe 4, which lay 0.73 m before the
// marker. Shifted by the marker's correction, the row's edge fell on stripe 4, as if stripe 4
// had been felt already; stripe 4 was dismissed as the marker's rival and its end taken for the
// marker (a calibration 0.73 m ahead of the truth). The row's edge is explained as it stands,
// so it says nothing about this one.
TEST(SamclTest, AnEarlierEdgeOnAnotherStripeDoesNotMakeAStripeEndAMarker) {
  const Eigen::Vector2d sensor = LeftInductiveInBase();
  // Stripe B ends 2 cm beyond the sensor's line, 0.73 m before the marker; stripe A crosses
  // the lane 0.74 m before B.
  MarkerSet markers = MarkersWithStripe({-0.73, 4.7 + sensor.y() - 0.02 + 1.0}, kPi / 2.0, 2.0);
  StripeMarker a = markers.markers.back();
  a.id = 8;
  a.stripe_id = 2;
  a.position_m = {-1.47, 4.7};
  a.length_m = 4.0;
  markers.markers.push_back(a);
  const double truth_at_a_m = -1.47 - sensor.x();
  // A tight cloud, as in the barn: A, behind, is no rival of the marker ahead.
  Samcl samcl = SamclAt(markers, truth_at_a_m, {0.03, 0.02, 0.005});
  EXPECT_NE(samcl.OnInductiveEdge({"inductive_left", 0})->outcome, CalibrationOutcome::kApplied);
  samcl.RecordOdometry(Pose2(0.74, 0, 0), 1'000'000'000);
  const CalibrationResult at_b = *samcl.OnInductiveEdge({"inductive_left", 1'000'000'000});
  EXPECT_EQ(at_b.outcome, CalibrationOutcome::kStripe);
  EXPECT_NEAR(samcl.amcl().PoseInMap(Pose2(0.74, 0, 0)).x_m(), truth_at_a_m + 0.74, 0.03);
}

TEST(SamclTest, AStripeBesideTheMarkerThatWasNeverFeltDoesNotBlockIt) {
  const Eigen::Vector2d sensor = LeftInductiveInBase();
  // 0.3 m along the lane before the marker, but ending 0.25 m aside of the sensor's line.
  const MarkerSet markers =
      MarkersWithStripe({-0.3, 4.7 + sensor.y() + 0.25 + 1.0}, kPi / 2.0, 2.0);
  const double truth_x_m = -sensor.x();  // the sensor on the marker
  Samcl samcl = SamclAt(markers, truth_x_m - 0.2, {0.2, 0.02, 0.005});
  const CalibrationResult r = *samcl.OnInductiveEdge({"inductive_left", 0});
  EXPECT_EQ(r.outcome, CalibrationOutcome::kApplied);
  EXPECT_NEAR(samcl.amcl().estimate().pose_in_map.x_m(), truth_x_m, 0.03);
}

// A barn's markers lie across the stripe the robot drives along; its sensors run beside the
// stripe and feel only the marker.
TEST(SamclTest, AMarkerAcrossTheStripeTheSensorsRunBesideIsCalibrated) {
  const MarkerSet markers = MarkersWithStripe({0.0, 4.7}, 0.0, 20.0);  // under the centre line
  const double truth_x_m = -LeftInductiveInBase().x();
  // Lateral spread of 0.1 m: the stripe's line is well within it.
  Samcl samcl = SamclAt(markers, truth_x_m - 0.2, {0.2, 0.1, 0.005});
  const CalibrationResult r = *samcl.OnInductiveEdge({"inductive_left", 0});
  EXPECT_EQ(r.outcome, CalibrationOutcome::kApplied);
  EXPECT_NEAR(samcl.amcl().estimate().pose_in_map.x_m(), truth_x_m, 0.03);
}

TEST(SamclTest, SoftCalibrationReweightsTowardsTheLine) {
  const OccupancyGrid map = Barn();
  const RobotModel model = LelyVectorModel();
  AmclParams params;
  params.min_particles = params.max_particles = 2000;
  Amcl amcl = *Amcl::Create(params, map);
  const Pose2 sensor = model.FindSensor("inductive_left")->pose_in_base;
  const Pose2 truth(-sensor.x_m(), 4.7, 0.0);
  // A wide along-track cloud, its mean 0.15 m behind the truth.
  ASSERT_TRUE(
      amcl.InitializePose(Pose2(truth.x_m() - 0.15, 4.7, 0), {0.3, 0.02, 0.005}, Pose2(), 0).ok());
  SamclParams soft;
  soft.mode = SamclMode::kSoft;
  Samcl samcl = *Samcl::Create(std::move(amcl), Experiment2Markers(), model, soft);
  samcl.RecordOdometry(Pose2(), 0);
  const CalibrationResult r = *samcl.OnInductiveEdge({"inductive_left", 0});
  EXPECT_EQ(r.outcome, CalibrationOutcome::kApplied);
  EXPECT_NEAR(samcl.amcl().estimate().pose_in_map.x_m(), truth.x_m(), 0.03);
  EXPECT_TRUE(samcl.amcl().last_update().resampled);
}

TEST(AmclTest, HealthTurnsLostWhenScansStopFitting) {
  const OccupancyGrid map = Barn();
  AmclParams params;
  params.min_particles = params.max_particles = 500;
  params.alpha_fast = 0.0;  // no recovery: only the health is under test
  params.alpha_slow = 0.0;
  Amcl amcl = *Amcl::Create(params, map);
  const Pose2 truth(-4.0, 2.5, 0.0);
  ASSERT_TRUE(amcl.InitializePose(truth, {0.05, 0.05, 0.02}, Pose2(), 0).ok());
  Rng rng(9);
  int64_t stamp = 0;
  for (int i = 0; i < 3; ++i) {
    stamp += 2'000'000'000;
    ASSERT_TRUE(amcl.Update(Pose2(), SimulateLaser(map, truth, 60, 12.0, 0.02, rng), stamp).ok());
  }
  EXPECT_FALSE(amcl.health().lost);
  const double good_confidence = amcl.health().confidence;
  // The scans now come from 5 m away.
  for (int i = 0; i < 4; ++i) {
    stamp += 2'000'000'000;
    ASSERT_TRUE(
        amcl.Update(Pose2(), SimulateLaser(map, Pose2(1.0, -1.0, 1.0), 60, 12.0, 0.02, rng), stamp)
            .ok());
  }
  EXPECT_TRUE(amcl.health().lost);
  EXPECT_LT(amcl.health().confidence, 0.5 * good_confidence);
}

}  // namespace
}  // namespace fleetnav::localization
