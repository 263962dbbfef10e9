// A job as a VDA order: sequence ids, the base that traffic clearances grow, and updates that
// start at the stitching node.
#include "fleetnav/vda5050/job_order.hpp"

#include <gtest/gtest.h>

namespace fleetnav::vda5050 {
namespace {

/// The vehicle's place, two waypoints of action 0 (the second its end), one of action 1.
std::vector<OrderWaypoint> TwoActions() {
  return {{0, 0, std::nullopt, 0, false},
          {1, 0, std::nullopt, 0, false},
          {2, 0, 0.0, 0, true},
          {2, 2, 1.57, 1, true}};
}

TEST(JobOrderTest, NodesAreEvenEdgesOddAndOnlyThePlaceIsReleasedBeforeAClearance) {
  absl::StatusOr<JobOrder> order = JobOrder::Create("job-1-5", "store", TwoActions());
  ASSERT_TRUE(order.ok()) << order.status();
  const Order first = order->First(-1);
  EXPECT_EQ(first.order_id, "job-1-5");
  EXPECT_EQ(first.order_update_id, 0u);
  ASSERT_EQ(first.nodes.size(), 4u);
  ASSERT_EQ(first.edges.size(), 3u);
  for (size_t i = 0; i < first.nodes.size(); ++i) {
    EXPECT_EQ(first.nodes[i].sequence_id, 2 * i);
    EXPECT_EQ(first.nodes[i].released, i == 0);
    EXPECT_EQ(first.nodes[i].position->map_id, "store");
  }
  for (size_t i = 0; i < first.edges.size(); ++i) {
    EXPECT_EQ(first.edges[i].sequence_id, 2 * i + 1);
    EXPECT_FALSE(first.edges[i].released);
    EXPECT_EQ(first.edges[i].start_node_id, first.nodes[i].node_id);
    EXPECT_EQ(first.edges[i].end_node_id, first.nodes[i + 1].node_id);
  }
  // Passing nodes carry the pass deviation, the end nodes their heading.
  EXPECT_DOUBLE_EQ(first.nodes[1].position->allowed_deviation_xy_m, 0.5);
  EXPECT_DOUBLE_EQ(*first.nodes[3].position->theta_rad, 1.57);
  EXPECT_EQ(order->EndNodeOf(0), 2u);
  EXPECT_EQ(order->EndNodeOf(1), 3u);
}

TEST(JobOrderTest, EachClearanceThatReachesFurtherIsAnUpdateFromTheStitchingNode) {
  absl::StatusOr<JobOrder> order = JobOrder::Create("job-1-5", "store", TwoActions());
  ASSERT_TRUE(order.ok());
  (void)order->First(-1);
  // Action 0 cleared: its nodes join the base; the update starts at the old last base node.
  std::optional<Order> update = order->Release(0);
  ASSERT_TRUE(update.has_value());
  EXPECT_EQ(update->order_update_id, 1u);
  ASSERT_EQ(update->nodes.size(), 4u);
  EXPECT_EQ(update->nodes[0].node_id, "job-1-5-n0");
  EXPECT_TRUE(update->nodes[2].released);
  EXPECT_FALSE(update->nodes[3].released);
  EXPECT_TRUE(update->edges[1].released);
  EXPECT_FALSE(update->edges[2].released);
  // The same clearance again releases nothing new.
  EXPECT_FALSE(order->Release(0).has_value());
  // Action 1: the update starts at node 2, the base's end so far; nothing before it again.
  update = order->Release(1);
  ASSERT_TRUE(update.has_value());
  EXPECT_EQ(update->order_update_id, 2u);
  ASSERT_EQ(update->nodes.size(), 2u);
  EXPECT_EQ(update->nodes[0].sequence_id, 4u);
  EXPECT_TRUE(update->nodes[1].released);
  ASSERT_EQ(update->edges.size(), 1u);
  EXPECT_EQ(update->edges[0].sequence_id, 5u);
  EXPECT_EQ(order->last().order_update_id, 2u);
}

TEST(JobOrderTest, BadWaypointsAreRefused) {
  EXPECT_FALSE(JobOrder::Create("o", "m", {{0, 0, std::nullopt, 0, true}}).ok());
  std::vector<OrderWaypoint> backwards = TwoActions();
  backwards[2].action_index = 1;
  backwards[3].action_index = 0;
  EXPECT_EQ(JobOrder::Create("o", "m", backwards).status().code(),
            absl::StatusCode::kInvalidArgument);
  std::vector<OrderWaypoint> open_end = TwoActions();
  open_end.back().action_end = false;
  EXPECT_FALSE(JobOrder::Create("o", "m", open_end).ok());
  EXPECT_FALSE(JobOrder::Create("", "m", TwoActions()).ok());
}

}  // namespace
}  // namespace fleetnav::vda5050
