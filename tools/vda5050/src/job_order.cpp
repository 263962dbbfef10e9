#include "fleetnav/vda5050/job_order.hpp"

#include "absl/strings/str_cat.h"

namespace fleetnav::vda5050 {

absl::StatusOr<JobOrder> JobOrder::Create(std::string order_id, std::string map_id,
                                          std::vector<OrderWaypoint> waypoints,
                                          JobOrderParams params) {
  if (order_id.empty()) return absl::InvalidArgumentError("order id: empty");
  if (waypoints.size() < 2) {
    return absl::InvalidArgumentError(
        "an order needs the vehicle's place and at least one waypoint");
  }
  for (size_t i = 1; i < waypoints.size(); ++i) {
    if (waypoints[i].action_index < waypoints[i - 1].action_index) {
      return absl::InvalidArgumentError(
          absl::StrCat("waypoint ", i, ": actions must come in order"));
    }
  }
  if (!waypoints.back().action_end) {
    return absl::InvalidArgumentError("the last waypoint must end its action");
  }
  return JobOrder(std::move(order_id), std::move(map_id), std::move(waypoints), params);
}

JobOrder::JobOrder(std::string order_id, std::string map_id, std::vector<OrderWaypoint> waypoints,
                   JobOrderParams params)
    : order_id_(std::move(order_id)),
      map_id_(std::move(map_id)),
      waypoints_(std::move(waypoints)),
      params_(params),
      action_count_(waypoints_.back().action_index + 1) {}

std::string JobOrder::NodeId(size_t index) const { return absl::StrCat(order_id_, "-n", index); }

size_t JobOrder::EndNodeOf(int action_index) const {
  for (size_t i = 1; i < waypoints_.size(); ++i) {
    if (waypoints_[i].action_index == action_index && waypoints_[i].action_end) return i;
  }
  return waypoints_.size() - 1;
}

size_t JobOrder::ReleasedNodes(int cleared_up_to_action) const {
  size_t released = 1;  // the vehicle's place
  while (released < waypoints_.size() &&
         waypoints_[released].action_index <= cleared_up_to_action) {
    ++released;
  }
  return released;
}

Order JobOrder::Message(size_t from_node, size_t released_nodes) const {
  Order order;
  order.order_id = order_id_;
  order.order_update_id = update_id_;
  for (size_t i = from_node; i < waypoints_.size(); ++i) {
    const OrderWaypoint& w = waypoints_[i];
    Node node;
    node.node_id = NodeId(i);
    node.sequence_id = static_cast<uint32_t>(2 * i);
    node.released = i < released_nodes;
    NodePosition position;
    position.x_m = w.x_m;
    position.y_m = w.y_m;
    position.theta_rad = w.theta_rad;
    position.map_id = map_id_;
    position.allowed_deviation_xy_m =
        w.action_end ? params_.end_deviation_m : params_.pass_deviation_m;
    if (w.action_end && w.theta_rad && params_.end_deviation_theta_rad > 0.0) {
      position.allowed_deviation_theta_rad = params_.end_deviation_theta_rad;
    }
    node.position = position;
    order.nodes.push_back(std::move(node));
    if (i + 1 < waypoints_.size()) {
      Edge edge;
      edge.edge_id = absl::StrCat(order_id_, "-e", i);
      edge.sequence_id = static_cast<uint32_t>(2 * i + 1);
      edge.released = i + 1 < released_nodes;  // both its nodes are released (§6.6.1)
      edge.start_node_id = NodeId(i);
      edge.end_node_id = NodeId(i + 1);
      order.edges.push_back(std::move(edge));
    }
  }
  return order;
}

Order JobOrder::First(int cleared_up_to_action) {
  update_id_ = 0;
  released_nodes_ = ReleasedNodes(cleared_up_to_action);
  last_ = Message(0, released_nodes_);
  return last_;
}

std::optional<Order> JobOrder::Release(int cleared_up_to_action) {
  const size_t released = ReleasedNodes(cleared_up_to_action);
  if (released <= released_nodes_) return std::nullopt;
  const size_t stitching_node = released_nodes_ - 1;
  ++update_id_;
  released_nodes_ = released;
  last_ = Message(stitching_node, released_nodes_);
  return last_;
}

}  // namespace fleetnav::vda5050
