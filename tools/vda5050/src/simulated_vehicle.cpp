#include "fleetnav/vda5050/simulated_vehicle.hpp"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/vda5050/vda_json.hpp"

namespace fleetnav::vda5050 {

SimulatedVehicle::SimulatedVehicle(SimulatedVehicleParams params)
    : params_(std::move(params)), pose_(params_.start) {}

void SimulatedVehicle::Refuse(const std::string& type, const std::string& why,
                              const std::string& order_id) {
  VehicleError error;
  error.error_type = type;
  error.description = why;
  error.level = ErrorLevel::kWarning;
  error.references = {{"orderId", order_id}};
  errors_.push_back(std::move(error));
}

void SimulatedVehicle::OnOrder(const std::string& json) {
  absl::StatusOr<Order> order = ParseOrder(json);
  if (!order.ok()) {
    Refuse("validationError", std::string(order.status().message()), "");
    return;
  }
  // §6.6.1: a graph of n nodes and n - 1 edges, sequence ids running over both.
  if (order->nodes.empty() || order->edges.size() + 1 != order->nodes.size()) {
    Refuse("validationError", "nodes and edges do not form a path (§6.6.1)", order->order_id);
    return;
  }
  for (size_t i = 0; i < order->nodes.size(); ++i) {
    if (!order->nodes[i].position) {
      Refuse("orderError", "a node without nodePosition", order->order_id);
      return;
    }
    if (i > 0 && order->nodes[i].sequence_id != order->nodes[i - 1].sequence_id + 2) {
      Refuse("validationError", "node sequence ids out of order (§6.6.2)", order->order_id);
      return;
    }
  }
  errors_.clear();
  if (order->order_id == order_id_) {
    if (order->order_update_id == order_update_id_) return;  // sent again (§6.6.4.3)
    if (order->order_update_id < order_update_id_) {
      Refuse("orderUpdateError",
             absl::StrCat("orderUpdateId ", order->order_update_id, " is below ", order_update_id_),
             order->order_id);
      return;
    }
    // §6.6.2: the update starts at the last base node, which the vehicle has passed or heads to.
    const Node& stitch = order->nodes.front();
    const bool at_stitch =
        stitch.node_id == last_node_id_ && stitch.sequence_id == last_node_sequence_id_;
    const auto pending = std::find_if(nodes_.begin(), nodes_.end(), [&](const Node& n) {
      return n.node_id == stitch.node_id && n.sequence_id == stitch.sequence_id;
    });
    if (!at_stitch && pending == nodes_.end()) {
      Refuse("orderUpdateError", "the update does not start at the last base node",
             order->order_id);
      return;
    }
    order_update_id_ = order->order_update_id;
    // The old horizon goes; the update's nodes from the stitching node on replace it.
    if (at_stitch) {
      nodes_.assign(order->nodes.begin() + 1, order->nodes.end());
    } else {
      nodes_.erase(pending, nodes_.end());
      nodes_.insert(nodes_.end(), order->nodes.begin(), order->nodes.end());
    }
    edges_ = order->edges;
    return;
  }
  if (!nodes_.empty()) {
    Refuse("orderError", absl::StrCat("order ", order_id_, " is still running"), order->order_id);
    return;
  }
  order_id_ = order->order_id;
  order_update_id_ = order->order_update_id;
  nodes_ = order->nodes;
  edges_ = order->edges;
  moved_this_order_ = false;
  action_states_.clear();
  // The first node is where the vehicle stands: passed at once (§6.6.1).
  last_node_id_ = nodes_.front().node_id;
  last_node_sequence_id_ = nodes_.front().sequence_id;
  nodes_.erase(nodes_.begin());
}

bool SimulatedVehicle::OnInstantActions(const std::string& json) {
  absl::StatusOr<InstantActions> message = ParseInstantActions(json);
  if (!message.ok()) {
    Refuse("validationError", std::string(message.status().message()), "");
    return false;
  }
  bool factsheet_asked = false;
  for (const Action& action : message->actions) {
    ActionState state{action.action_id, action.action_type, ActionStatus::kFinished, ""};
    if (action.action_type == "cancelOrder") {
      if (nodes_.empty()) {
        state.status = ActionStatus::kFailed;
        VehicleError error;
        error.error_type = "noOrderToCancel";
        error.references = {{"actionId", action.action_id}};
        errors_.push_back(error);
      }
      nodes_.clear();
      edges_.clear();
      driving_ = false;
    } else if (action.action_type == "startPause") {
      paused_ = true;
      driving_ = false;
    } else if (action.action_type == "stopPause") {
      paused_ = false;
    } else if (action.action_type == "factsheetRequest") {
      factsheet_asked = true;
    } else {
      state.status = ActionStatus::kFailed;
      state.result_description = "not supported";
    }
    action_states_.push_back(state);
  }
  return factsheet_asked;
}

const Node* SimulatedVehicle::NextTarget() const {
  if (nodes_.empty() || !nodes_.front().released) return nullptr;
  return &nodes_.front();
}

VehicleStepEvents SimulatedVehicle::Step(double dt_s, int64_t /*unix_ms*/) {
  VehicleStepEvents events;
  const Node* target = paused_ ? nullptr : NextTarget();
  const bool was_driving = driving_;
  driving_ = false;
  if (target != nullptr) {
    const NodePosition& at = *target->position;
    const Eigen::Vector2d to = Eigen::Vector2d(at.x_m, at.y_m) - pose_.translation();
    const double tolerance =
        at.allowed_deviation_xy_m > 0.0 ? at.allowed_deviation_xy_m : params_.node_tolerance_m;
    const bool last = nodes_.size() == 1 || !nodes_[1].released;
    // Passing nodes are passed within their deviation; the last released one is reached.
    const double reach = last ? std::min(tolerance, params_.node_tolerance_m) : tolerance;
    double yaw = pose_.yaw_rad();
    if (at.theta_rad) {
      const double turn = NormalizeAngle(*at.theta_rad - yaw);
      yaw += std::clamp(turn, -params_.yaw_rate_radps * dt_s, params_.yaw_rate_radps * dt_s);
    }
    const bool heading_ok =
        !at.theta_rad || !last || std::abs(NormalizeAngle(*at.theta_rad - yaw)) < 0.02;
    if (to.norm() <= reach && heading_ok) {
      last_node_id_ = target->node_id;
      last_node_sequence_id_ = target->sequence_id;
      nodes_.erase(nodes_.begin());
      if (!edges_.empty() && edges_.front().end_node_id == last_node_id_) {
        edges_.erase(edges_.begin());
      }
      events.changed = true;
      pose_ = Pose2(pose_.x_m(), pose_.y_m(), yaw);
    } else {
      const double step = std::min(to.norm(), params_.speed_mps * dt_s);
      const Eigen::Vector2d move =
          to.norm() > 1e-9 ? Eigen::Vector2d(to.normalized() * step) : Eigen::Vector2d::Zero();
      pose_ = Pose2(pose_.x_m() + move.x(), pose_.y_m() + move.y(), yaw);
      driving_ = true;
      if (!moved_this_order_) {
        moved_this_order_ = true;
        events.first_motion = true;
        events.moving_order_id = order_id_;
      }
    }
  }
  if (driving_ != was_driving) events.changed = true;
  return events;
}

Header SimulatedVehicle::NextHeader(uint32_t* counter, int64_t unix_ms) const {
  Header header;
  header.header_id = (*counter)++;
  header.timestamp = Timestamp(unix_ms);
  header.manufacturer = params_.manufacturer;
  header.serial_number = params_.serial_number;
  return header;
}

State SimulatedVehicle::MakeState(int64_t unix_ms) {
  State state;
  state.header = NextHeader(&state_header_id_, unix_ms);
  state.order_id = order_id_;
  state.order_update_id = order_update_id_;
  state.last_node_id = last_node_id_;
  state.last_node_sequence_id = last_node_sequence_id_;
  for (const Node& node : nodes_) {
    state.node_states.push_back({node.node_id, node.sequence_id, node.released});
  }
  for (const Edge& edge : edges_) {
    state.edge_states.push_back({edge.edge_id, edge.sequence_id, edge.released});
  }
  state.driving = driving_;
  state.paused = paused_;
  state.agv_position =
      AgvPosition{pose_.x_m(), pose_.y_m(), pose_.yaw_rad(), params_.map_id, true, 1.0};
  state.velocity = Velocity{driving_ ? params_.speed_mps : 0.0, 0.0, 0.0};
  state.action_states = action_states_;
  state.battery_charge_percent = 80.0;
  state.errors = errors_;
  return state;
}

Connection SimulatedVehicle::MakeConnection(ConnectionState connection_state, int64_t unix_ms) {
  Connection connection;
  connection.header = NextHeader(&connection_header_id_, unix_ms);
  connection.state = connection_state;
  return connection;
}

Factsheet SimulatedVehicle::MakeFactsheet(int64_t unix_ms) {
  Factsheet factsheet = params_.factsheet;
  factsheet.header = NextHeader(&factsheet_header_id_, unix_ms);
  return factsheet;
}

}  // namespace fleetnav::vda5050
