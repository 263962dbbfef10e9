#include "fleetnav/proto/telemetry_convert.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>
#include <string>

namespace fleetnav {
namespace {

using ::testing::HasSubstr;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

template <typename T>
void ExpectInvalid(const absl::StatusOr<T>& result, const std::string& field) {
  ASSERT_FALSE(result.ok()) << "expected InvalidArgument naming '" << field << "'";
  EXPECT_EQ(result.status().code(), absl::StatusCode::kInvalidArgument) << result.status();
  EXPECT_THAT(std::string(result.status().message()), HasSubstr(field));
}

Telemetry SampleTelemetry() {
  Telemetry t;
  t.stamp_ns = 123'456'789'012;
  t.sequence = 42;
  t.pose_in_map = Pose2(10.5, -3.25, 1.2);
  t.covariance = {0.01, 0.001, 0.0, 0.001, 0.02, 0.0, 0.0, 0.0, 0.005};
  t.pose_in_odom = Pose2(9.75, -3.0, 1.15);
  t.velocity = {0.4, 0.0, -0.1};
  t.mode = NavigationMode::kStripeMapBased;
  t.localization_confidence = 0.87;
  t.localization_lost = true;
  t.battery_fraction = 0.66;
  t.job_id = "job-17";
  t.action_index = 3;
  t.job_progress_fraction = 0.25;
  t.carried_load_m = Eigen::Vector2d(1.04, 0.74);
  return t;
}

TEST(TelemetryConvertTest, RoundTripsEveryField) {
  const Telemetry t = SampleTelemetry();
  const v1::Telemetry wire = ToProto(t);
  EXPECT_EQ(wire.mode(), v1::NAVIGATION_MODE_STRIPE_MAP_BASED);
  EXPECT_EQ(wire.pose_in_map().covariance_size(), 9);
  const absl::StatusOr<Telemetry> back = FromProto(wire);
  ASSERT_TRUE(back.ok()) << back.status();
  EXPECT_EQ(back->stamp_ns, t.stamp_ns);
  EXPECT_EQ(back->sequence, t.sequence);
  EXPECT_TRUE(back->pose_in_map.IsNear(t.pose_in_map, 0.0, 0.0));
  EXPECT_EQ(back->covariance, t.covariance);
  EXPECT_TRUE(back->pose_in_odom.IsNear(t.pose_in_odom, 0.0, 0.0));
  EXPECT_EQ(back->velocity.vx_mps, t.velocity.vx_mps);
  EXPECT_EQ(back->velocity.vy_mps, t.velocity.vy_mps);
  EXPECT_EQ(back->velocity.yaw_rate_radps, t.velocity.yaw_rate_radps);
  EXPECT_EQ(back->mode, t.mode);
  EXPECT_EQ(back->localization_confidence, t.localization_confidence);
  EXPECT_EQ(back->localization_lost, t.localization_lost);
  EXPECT_EQ(back->battery_fraction, t.battery_fraction);
  EXPECT_EQ(back->job_id, t.job_id);
  EXPECT_EQ(back->action_index, t.action_index);
  EXPECT_EQ(back->job_progress_fraction, t.job_progress_fraction);
  ASSERT_TRUE(back->carried_load_m.has_value());
  EXPECT_EQ(*back->carried_load_m, *t.carried_load_m);
}

TEST(TelemetryConvertTest, AnEmptyLiftStaysEmptyAndANonsenseLoadIsRefused) {
  Telemetry t = SampleTelemetry();
  t.carried_load_m.reset();
  const v1::Telemetry wire = ToProto(t);
  EXPECT_FALSE(wire.has_carried_load_size());
  const absl::StatusOr<Telemetry> back = FromProto(wire);
  ASSERT_TRUE(back.ok()) << back.status();
  EXPECT_FALSE(back->carried_load_m.has_value());

  v1::Telemetry bad = ToProto(SampleTelemetry());
  bad.mutable_carried_load_size()->set_y_m(0.0);
  ExpectInvalid(FromProto(bad), "telemetry.carried_load_size");
  bad.mutable_carried_load_size()->set_y_m(kNan);
  ExpectInvalid(FromProto(bad), "telemetry.carried_load_size");
}

TEST(TelemetryConvertTest, EveryNavigationModeRoundTrips) {
  for (int m = static_cast<int>(NavigationMode::kIdle);
       m <= static_cast<int>(NavigationMode::kFault); ++m) {
    const auto mode = static_cast<NavigationMode>(m);
    const v1::NavigationMode wire = ToProto(mode);
    EXPECT_NE(wire, v1::NAVIGATION_MODE_UNSPECIFIED);
    const absl::StatusOr<NavigationMode> back = NavigationModeFromProto(wire);
    ASSERT_TRUE(back.ok()) << back.status();
    EXPECT_EQ(*back, mode);
  }
  EXPECT_EQ(ToProto(NavigationMode::kIdle), v1::NAVIGATION_MODE_IDLE);
  EXPECT_EQ(ToProto(NavigationMode::kFault), v1::NAVIGATION_MODE_FAULT);
  EXPECT_EQ(ToProto(NavigationMode::kDocking), v1::NAVIGATION_MODE_DOCKING);
}

TEST(TelemetryConvertTest, UnspecifiedModeIsIdleAndUnknownModeIsRefused) {
  const absl::StatusOr<NavigationMode> idle =
      NavigationModeFromProto(v1::NAVIGATION_MODE_UNSPECIFIED);
  ASSERT_TRUE(idle.ok());
  EXPECT_EQ(*idle, NavigationMode::kIdle);
  ExpectInvalid(NavigationModeFromProto(99), "telemetry.mode");
  ExpectInvalid(NavigationModeFromProto(-1), "telemetry.mode");

  v1::Telemetry wire = ToProto(SampleTelemetry());
  wire.set_mode(static_cast<v1::NavigationMode>(99));
  ExpectInvalid(FromProto(wire), "telemetry.mode");
}

TEST(TelemetryConvertTest, ConnectionStatesMap) {
  EXPECT_EQ(ToProto(ConnectionState::kOnline), v1::CONNECTION_STATE_ONLINE);
  EXPECT_EQ(ToProto(ConnectionState::kStale), v1::CONNECTION_STATE_STALE);
  EXPECT_EQ(ToProto(ConnectionState::kOffline), v1::CONNECTION_STATE_OFFLINE);
}

TEST(TelemetryConvertTest, AcceptsMissingCovarianceAsZeros) {
  v1::Telemetry wire = ToProto(SampleTelemetry());
  wire.mutable_pose_in_map()->clear_covariance();
  const absl::StatusOr<Telemetry> back = FromProto(wire);
  ASSERT_TRUE(back.ok()) << back.status();
  for (double c : back->covariance) EXPECT_EQ(c, 0.0);
}

TEST(TelemetryConvertTest, RefusesCovarianceWithFiveValues) {
  v1::Telemetry wire = ToProto(SampleTelemetry());
  wire.mutable_pose_in_map()->clear_covariance();
  for (int i = 0; i < 5; ++i) wire.mutable_pose_in_map()->add_covariance(0.1);
  const absl::StatusOr<Telemetry> result = FromProto(wire);
  ExpectInvalid(result, "telemetry.pose_in_map.covariance");
  EXPECT_THAT(std::string(result.status().message()), HasSubstr("got 5"));
}

TEST(TelemetryConvertTest, RefusesNanCovarianceEntry) {
  v1::Telemetry wire = ToProto(SampleTelemetry());
  wire.mutable_pose_in_map()->set_covariance(4, kNan);
  ExpectInvalid(FromProto(wire), "telemetry.pose_in_map.covariance[4]");
}

TEST(TelemetryConvertTest, RefusesNanPosesAndVelocity) {
  v1::Telemetry wire = ToProto(SampleTelemetry());
  wire.mutable_pose_in_map()->mutable_pose()->set_x_m(kNan);
  ExpectInvalid(FromProto(wire), "telemetry.pose_in_map");
  wire = ToProto(SampleTelemetry());
  wire.mutable_pose_in_odom()->set_yaw_rad(kNan);
  ExpectInvalid(FromProto(wire), "telemetry.pose_in_odom");
  wire = ToProto(SampleTelemetry());
  wire.mutable_velocity()->set_vy_mps(kNan);
  ExpectInvalid(FromProto(wire), "telemetry.velocity");
}

RobotIdentity SampleIdentity() {
  RobotIdentity identity;
  identity.robot_id = "vector-01.barn_A";
  identity.model = LelyVectorModel();
  identity.capabilities = {"feed", "push"};
  identity.software_version = "1.4.2";
  return identity;
}

TEST(AgentHelloConvertTest, RoundTrips) {
  const RobotIdentity identity = SampleIdentity();
  const v1::AgentHello wire = ToProto(identity);
  EXPECT_EQ(wire.robot_id(), identity.robot_id);
  EXPECT_EQ(wire.model().kind_name(), "lely-vector");
  const absl::StatusOr<RobotIdentity> back = FromProto(wire);
  ASSERT_TRUE(back.ok()) << back.status();
  EXPECT_EQ(back->robot_id, identity.robot_id);
  EXPECT_EQ(back->model.kind_name, identity.model.kind_name);
  EXPECT_EQ(back->model.kinematics, identity.model.kinematics);
  EXPECT_EQ(back->model.footprint_m, identity.model.footprint_m);
  EXPECT_EQ(back->model.sensors.size(), identity.model.sensors.size());
  EXPECT_EQ(back->capabilities, identity.capabilities);
  EXPECT_EQ(back->software_version, identity.software_version);
}

TEST(AgentHelloConvertTest, AcceptsIdOfSixtyFourAllowedCharacters) {
  RobotIdentity identity = SampleIdentity();
  identity.robot_id = std::string(64, 'r');
  EXPECT_TRUE(FromProto(ToProto(identity)).ok());
}

TEST(AgentHelloConvertTest, RefusesEmptyOrBadRobotId) {
  for (const std::string& bad :
       {std::string(), std::string(65, 'r'), std::string("robot 1"), std::string("a/b"),
        std::string("r\xc3\xa9"), std::string("id\0x", 4)}) {
    SCOPED_TRACE("robot_id '" + bad + "'");
    RobotIdentity identity = SampleIdentity();
    identity.robot_id = bad;
    ExpectInvalid(FromProto(ToProto(identity)), "hello.robot_id");
  }
}

TEST(AgentHelloConvertTest, RefusesHelloWithoutModel) {
  v1::AgentHello wire = ToProto(SampleIdentity());
  wire.clear_model();
  ExpectInvalid(FromProto(wire), "model.kinematics");
}

TEST(TelemetryConvertTest, ARobotRecordBecomesTheOperatorsRobotState) {
  RobotRecord record;
  record.identity.robot_id = "lely1";
  record.identity.model = LelyVectorModel();
  record.identity.capabilities = {"straight", "turn"};
  record.identity.software_version = "0.1.0";
  record.connection = ConnectionState::kStale;
  Telemetry telemetry;
  telemetry.battery_fraction = 0.5;
  record.last_telemetry = telemetry;
  record.last_seen_ns = 42;
  record.current_job_id = "job-7";
  record.traffic_wait = "waits for lely2";
  record.traffic_held_s = 12.5;
  const v1::RobotState wire = ToProto(record);
  EXPECT_EQ(wire.robot_id(), "lely1");
  EXPECT_EQ(wire.kind_name(), record.identity.model.kind_name);
  ASSERT_EQ(wire.capabilities_size(), 2);
  EXPECT_EQ(wire.capabilities(1), "turn");
  EXPECT_EQ(wire.software_version(), "0.1.0");
  EXPECT_EQ(wire.connection(), v1::CONNECTION_STATE_STALE);
  ASSERT_TRUE(wire.has_last_telemetry());
  EXPECT_DOUBLE_EQ(wire.last_telemetry().battery_fraction(), 0.5);
  EXPECT_EQ(wire.last_seen_ns(), 42);
  EXPECT_EQ(wire.current_job_id(), "job-7");
  EXPECT_EQ(wire.traffic_wait(), "waits for lely2");
  EXPECT_DOUBLE_EQ(wire.traffic_held_s(), 12.5);
  record.last_telemetry.reset();
  EXPECT_FALSE(ToProto(record).has_last_telemetry());
}

}  // namespace
}  // namespace fleetnav
