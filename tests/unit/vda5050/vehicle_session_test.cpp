// What a vehicle's state means for its fleetnav job: telemetry, actions started and finished
// as it passes their end nodes, success, failure on a refused order, stale header ids.
#include "fleetnav/vda5050/vehicle_session.hpp"

#include <gtest/gtest.h>

namespace fleetnav::vda5050 {
namespace {

JobOrder TwoActionOrder() {
  return *JobOrder::Create("job-1-5", "store",
                           {{0, 0, std::nullopt, 0, false},
                            {1, 0, std::nullopt, 0, false},
                            {2, 0, 0.0, 0, true},
                            {2, 2, 1.57, 1, true}});
}

State StateAt(const std::string& order_id, uint32_t passed_node, bool driving) {
  State state;
  state.order_id = order_id;
  state.last_node_id = "job-1-5-n" + std::to_string(passed_node);
  state.last_node_sequence_id = 2 * passed_node;
  state.driving = driving;
  state.agv_position = AgvPosition{1.0, 2.0, 0.3, "store", true, 0.8};
  state.battery_charge_percent = 55.0;
  return state;
}

std::vector<JobEventType> Types(const std::vector<JobEvent>& events) {
  std::vector<JobEventType> types;
  for (const JobEvent& event : events) types.push_back(event.type);
  return types;
}

TEST(VehicleSessionTest, HeaderIdsMustGrowPerTopic) {
  VehicleSession session("vda-acme-0001");
  EXPECT_TRUE(session.Fresh("state", 5));
  EXPECT_FALSE(session.Fresh("state", 5));
  EXPECT_FALSE(session.Fresh("state", 4));
  EXPECT_TRUE(session.Fresh("visualization", 1));  // counted per topic
  EXPECT_TRUE(session.Fresh("state", 6));
  session.ResetHeaders();
  EXPECT_TRUE(session.Fresh("state", 1));
}

TEST(VehicleSessionTest, ActionsStartWhenClearedAndFinishAtTheirEndNodes) {
  VehicleSession session("vda-acme-0001");
  const Order first = session.Start("job-1", TwoActionOrder());
  EXPECT_FALSE(first.nodes[1].released);
  // Driving before a clearance starts nothing.
  VehicleSession::Outcome out = session.OnState(StateAt("job-1-5", 0, true), 100);
  EXPECT_TRUE(out.events.empty());
  EXPECT_EQ(out.telemetry.job_id, "job-1");
  EXPECT_DOUBLE_EQ(out.telemetry.pose_in_map.x_m(), 1.0);
  EXPECT_DOUBLE_EQ(out.telemetry.battery_fraction, 0.55);
  EXPECT_DOUBLE_EQ(out.telemetry.localization_confidence, 0.8);

  std::optional<Order> update = session.Clear("job-1", 0);
  ASSERT_TRUE(update.has_value());
  out = session.OnState(StateAt("job-1-5", 0, true), 200);
  EXPECT_EQ(Types(out.events), std::vector<JobEventType>{JobEventType::kActionStarted});
  EXPECT_EQ(out.events[0].action_index, 0);
  out = session.OnState(StateAt("job-1-5", 1, true), 300);  // a passing node
  EXPECT_TRUE(out.events.empty());
  EXPECT_NEAR(out.telemetry.job_progress_fraction, 1.0 / 3.0, 1e-9);
  out = session.OnState(StateAt("job-1-5", 2, false), 400);  // action 0's end
  EXPECT_EQ(Types(out.events), std::vector<JobEventType>{JobEventType::kActionFinished});
  EXPECT_EQ(out.telemetry.action_index, 1);
  ASSERT_TRUE(session.Clear("job-1", 1).has_value());
  out = session.OnState(StateAt("job-1-5", 3, false), 500);  // the last node
  EXPECT_EQ(Types(out.events),
            (std::vector<JobEventType>{JobEventType::kActionStarted, JobEventType::kActionFinished,
                                       JobEventType::kSucceeded}));
  EXPECT_EQ(session.job_id(), "");
}

TEST(VehicleSessionTest, ARefusedOrderFailsTheJobWithTheVehiclesReason) {
  VehicleSession session("vda-acme-0001");
  (void)session.Start("job-1", TwoActionOrder());
  State state = StateAt("", 0, false);  // still without our order
  VehicleError error;
  error.error_type = "orderError";
  error.description = "a node without nodePosition";
  error.references = {{"orderId", "job-1-5"}};
  state.errors.push_back(error);
  const VehicleSession::Outcome out = session.OnState(state, 100);
  ASSERT_EQ(out.events.size(), 1u);
  EXPECT_EQ(out.events[0].type, JobEventType::kFailed);
  EXPECT_EQ(out.events[0].reason, "the vehicle reports orderError: a node without nodePosition");
  EXPECT_EQ(session.job_id(), "");
}

TEST(VehicleSessionTest, AnotherOrdersErrorOrAWarningLeavesTheJobRunning) {
  VehicleSession session("vda-acme-0001");
  (void)session.Start("job-1", TwoActionOrder());
  State state = StateAt("job-1-5", 0, false);
  VehicleError old;
  old.error_type = "orderError";
  old.references = {{"orderId", "job-0-1"}};
  state.errors.push_back(old);
  VehicleError warning;
  warning.error_type = "orderUpdateError";
  state.errors.push_back(warning);
  EXPECT_TRUE(session.OnState(state, 100).events.empty());
  EXPECT_EQ(session.job_id(), "job-1");
  VehicleError fatal;
  fatal.error_type = "motorFault";
  fatal.level = ErrorLevel::kFatal;
  state.errors = {fatal};
  const VehicleSession::Outcome out = session.OnState(state, 200);
  ASSERT_EQ(out.events.size(), 1u);
  EXPECT_EQ(out.events[0].type, JobEventType::kFailed);
}

TEST(VehicleSessionTest, CommandsBecomeInstantActionsAndAnEarlyClearanceIsKept) {
  VehicleSession session("vda-acme-0001");
  EXPECT_FALSE(session.Clear("job-1", 0).has_value());  // before the job starts
  const Order first = session.Start("job-1", TwoActionOrder());
  EXPECT_TRUE(first.nodes[2].released);  // the early clearance applied
  std::vector<JobEvent> events;
  std::optional<Action> pause =
      session.Command({JobCommandType::kPause, "job-1", "operator", -1}, "a1", &events);
  ASSERT_TRUE(pause.has_value());
  EXPECT_EQ(pause->action_type, "startPause");
  EXPECT_EQ(session.Command({JobCommandType::kResume, "job-1", "", -1}, "a2", &events)->action_type,
            "stopPause");
  EXPECT_FALSE(session.Command({JobCommandType::kCancel, "job-9", "", -1}, "a3", &events));
  std::optional<Action> cancel =
      session.Command({JobCommandType::kCancel, "job-1", "operator", -1}, "a4", &events);
  ASSERT_TRUE(cancel.has_value());
  EXPECT_EQ(cancel->action_type, "cancelOrder");
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].type, JobEventType::kCancelled);
  EXPECT_EQ(session.job_id(), "");
}

}  // namespace
}  // namespace fleetnav::vda5050
