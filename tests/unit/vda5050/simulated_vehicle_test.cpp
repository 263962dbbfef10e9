// The simulated VDA vehicle keeps the protocol's order rules (§6.6): it drives only the base,
// takes an update only from its last base node with a higher orderUpdateId, ignores a resend,
// refuses a new order while one runs, and answers cancelOrder.
#include "fleetnav/vda5050/simulated_vehicle.hpp"

#include <gtest/gtest.h>

#include "fleetnav/vda5050/job_order.hpp"
#include "fleetnav/vda5050/vda_json.hpp"

namespace fleetnav::vda5050 {
namespace {

SimulatedVehicle Vehicle() {
  SimulatedVehicleParams params;
  params.map_id = "store";
  params.speed_mps = 1.0;
  return SimulatedVehicle(params);
}

JobOrder Straight() {
  return *JobOrder::Create(
      "o-1", "store",
      {{0, 0, std::nullopt, 0, false}, {2, 0, std::nullopt, 0, true}, {4, 0, 0.0, 1, true}});
}

std::string Json(Order order) {
  order.header = {0, "2026-11-26T05:40:03.120Z", "2.0.0", "acme", "0001"};
  return ToJson(order);
}

void Drive(SimulatedVehicle& vehicle, double seconds) {
  for (int i = 0; i < static_cast<int>(seconds * 50); ++i) vehicle.Step(0.02, 0);
}

TEST(SimulatedVehicleTest, DrivesTheBaseOnlyAndTakesUpdatesFromTheStitchingNode) {
  SimulatedVehicle vehicle = Vehicle();
  JobOrder order = Straight();
  vehicle.OnOrder(Json(order.First(0)));  // action 0 released: up to x = 2
  Drive(vehicle, 5.0);
  EXPECT_NEAR(vehicle.pose().x_m(), 2.0, 0.06);
  EXPECT_FALSE(vehicle.driving());
  State state = vehicle.MakeState(0);
  EXPECT_EQ(state.last_node_id, "o-1-n1");
  EXPECT_EQ(state.last_node_sequence_id, 2u);
  ASSERT_EQ(state.node_states.size(), 1u);
  EXPECT_FALSE(state.node_states[0].released);

  vehicle.OnOrder(Json(*order.Release(1)));
  Drive(vehicle, 5.0);
  EXPECT_NEAR(vehicle.pose().x_m(), 4.0, 0.06);
  state = vehicle.MakeState(0);
  EXPECT_EQ(state.last_node_sequence_id, 4u);
  EXPECT_TRUE(state.node_states.empty());
  EXPECT_TRUE(state.errors.empty());
}

TEST(SimulatedVehicleTest, OrderRulesOfTheSpecification) {
  SimulatedVehicle vehicle = Vehicle();
  JobOrder order = Straight();
  const Order first = order.First(-1);
  vehicle.OnOrder(Json(first));
  const Order update = *order.Release(0);
  vehicle.OnOrder(Json(update));
  vehicle.OnOrder(Json(update));  // a resend: ignored
  EXPECT_TRUE(vehicle.MakeState(0).errors.empty());
  vehicle.OnOrder(Json(first));  // a lower orderUpdateId
  ASSERT_EQ(vehicle.errors().size(), 1u);
  EXPECT_EQ(vehicle.errors()[0].error_type, "orderUpdateError");
  // A new order while this one runs.
  JobOrder other =
      *JobOrder::Create("o-2", "store", {{0, 0, std::nullopt, 0, false}, {1, 1, 0.0, 0, true}});
  vehicle.OnOrder(Json(other.First(0)));
  EXPECT_EQ(vehicle.errors().back().error_type, "orderError");
  EXPECT_EQ(vehicle.order_id(), "o-1");
  // Malformed.
  vehicle.OnOrder("{\"orderId\": 3}");
  EXPECT_EQ(vehicle.errors().back().error_type, "validationError");
}

TEST(SimulatedVehicleTest, CancelOrderStopsTheVehicle) {
  SimulatedVehicle vehicle = Vehicle();
  JobOrder order = Straight();
  vehicle.OnOrder(Json(order.First(1)));
  Drive(vehicle, 1.0);
  EXPECT_TRUE(vehicle.driving());
  InstantActions cancel;
  cancel.header = {0, "2026-11-26T05:40:03.120Z", "2.0.0", "acme", "0001"};
  cancel.actions.push_back({"cancelOrder", "c1", "", BlockingType::kHard, {}});
  vehicle.OnInstantActions(ToJson(cancel));
  const double x = vehicle.pose().x_m();
  Drive(vehicle, 1.0);
  EXPECT_DOUBLE_EQ(vehicle.pose().x_m(), x);
  const State state = vehicle.MakeState(0);
  ASSERT_EQ(state.action_states.size(), 1u);
  EXPECT_EQ(state.action_states[0].status, ActionStatus::kFinished);
  EXPECT_TRUE(state.node_states.empty());
}

}  // namespace
}  // namespace fleetnav::vda5050
