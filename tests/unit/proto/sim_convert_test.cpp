#include "fleetnav/proto/sim_convert.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace fleetnav {
namespace {

using ::testing::HasSubstr;

TEST(SimConvertTest, EveryFaultCrossesTheWireUnchanged) {
  for (FaultType type : {FaultType::kHideUltrasonicRegion, FaultType::kRemoveFenceSegment,
                         FaultType::kRemoveStripeSegment, FaultType::kWheelSlipRegion,
                         FaultType::kSensorDropout, FaultType::kSlowDown}) {
    FaultSpec fault;
    fault.type = type;
    fault.region_min_m = {1.0, -2.0};
    fault.region_max_m = {3.5, 4.0};
    fault.robot_id = "lely1";
    fault.sensor_name = "laser";
    fault.duration_s = 12.5;
    fault.factor = 0.4;
    const absl::StatusOr<FaultSpec> back = FromProto(ToProto(fault));
    ASSERT_TRUE(back.ok()) << back.status();
    EXPECT_EQ(back->type, type) << FaultTypeName(type);
    EXPECT_EQ(back->region_min_m, fault.region_min_m);
    EXPECT_EQ(back->region_max_m, fault.region_max_m);
    EXPECT_EQ(back->robot_id, "lely1");
    EXPECT_EQ(back->sensor_name, "laser");
    EXPECT_DOUBLE_EQ(back->duration_s, 12.5);
    EXPECT_DOUBLE_EQ(back->factor, 0.4);
  }
}

TEST(SimConvertTest, BadFaultRequestsAreRefusedNamingTheField) {
  v1::InjectFaultRequest unspecified;
  EXPECT_THAT(FromProto(unspecified).status().message(), HasSubstr("type:"));
  v1::InjectFaultRequest slip;
  slip.set_type(v1::FAULT_TYPE_WHEEL_SLIP_REGION);
  EXPECT_THAT(FromProto(slip).status().message(), HasSubstr("factor:"));
  v1::InjectFaultRequest nan_region;
  nan_region.set_type(v1::FAULT_TYPE_REMOVE_FENCE_SEGMENT);
  nan_region.mutable_region_max()->set_x_m(std::nan(""));
  EXPECT_EQ(FromProto(nan_region).status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(FromProto(nan_region).status().message(), HasSubstr("region_max"));
  // No factor given: 1 (no change), except a slow-down, where 0 stops the robot.
  v1::InjectFaultRequest fence;
  fence.set_type(v1::FAULT_TYPE_REMOVE_FENCE_SEGMENT);
  EXPECT_DOUBLE_EQ(FromProto(fence)->factor, 1.0);
  v1::InjectFaultRequest stop;
  stop.set_type(v1::FAULT_TYPE_SLOW_DOWN);
  EXPECT_DOUBLE_EQ(FromProto(stop)->factor, 0.0);
}

TEST(SimConvertTest, GroundTruthCarriesCollisionsTrolleysContactsAndTheCalendar) {
  GroundTruthSnapshot truth;
  truth.tick = 42;
  truth.sim_time_ns = 840'000'000;
  RobotTruth robot;
  robot.robot_id = "omni1";
  robot.pose = Pose2(1.0, 2.0, 0.5);
  robot.velocity.vy_mps = 0.2;
  robot.collisions_world = 2;
  robot.collisions_robots = 1;
  truth.robots.push_back(robot);
  truth.trolleys.push_back({"t1", Pose2(4.0, 4.0, 0.0), "omni1"});
  truth.contacts.push_back({"omni1", "static", 500'000'000});
  truth.min_separation_m = std::numeric_limits<double>::infinity();
  const v1::GroundTruth wire = ToProto(truth, 1'700'000'000'000);
  EXPECT_EQ(wire.tick(), 42u);
  EXPECT_EQ(wire.start_unix_ms(), 1'700'000'000'000);
  ASSERT_EQ(wire.robots_size(), 1);
  EXPECT_EQ(wire.robots(0).collisions(), 3u);
  EXPECT_EQ(wire.robots(0).collisions_robots(), 1u);
  EXPECT_DOUBLE_EQ(wire.robots(0).velocity().vy_mps(), 0.2);
  EXPECT_DOUBLE_EQ(wire.robots(0).pose().yaw_rad(), 0.5);
  EXPECT_EQ(wire.trolleys(0).carrier_robot_id(), "omni1");
  EXPECT_EQ(wire.contacts(0).other(), "static");
  EXPECT_DOUBLE_EQ(wire.min_separation_m(), 1e9);  // fewer than two robots
}

TEST(SimConvertTest, TheWorldListsItsRobotsWithTheirModels) {
  SimWorldSummary world;
  world.world_name = "barn";
  world.width_m = 30.0;
  world.robots.push_back({"lely1", LelyVectorModel(), true});
  world.robots.push_back({"ghost", std::nullopt, false});
  const v1::GetWorldResponse wire = ToProto(world);
  EXPECT_EQ(wire.world_name(), "barn");
  ASSERT_EQ(wire.robots_size(), 2);
  EXPECT_TRUE(wire.robots(0).attached());
  EXPECT_TRUE(wire.robots(0).has_model());
  EXPECT_FALSE(wire.robots(1).has_model());
}

}  // namespace
}  // namespace fleetnav
