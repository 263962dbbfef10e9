#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/vda5050/vda_messages.hpp"

namespace fleetnav::vda5050 {

/// A place the vehicle drives through, with the job action it belongs to.
struct OrderWaypoint {
  double x_m = 0.0;
  double y_m = 0.0;
  std::optional<double> theta_rad;  ///< set where the action ends at a heading (its goal)
  int action_index = 0;
  bool action_end = false;  ///< the last waypoint of its action
};

struct JobOrderParams {
  /// allowedDeviationXY of nodes the vehicle only passes, and of each action's end node
  /// (0: the vehicle's own tolerance).
  double pass_deviation_m = 0.5;
  double end_deviation_m = 0.0;
  double end_deviation_theta_rad = 0.0;  ///< 0: the vehicle's own
};

/// One fleetnav job as one VDA 5050 order (§6.6): the vehicle's place and then the job's
/// waypoints as nodes (sequence ids 0, 2, 4 …) joined by edges (1, 3, …), each node carrying
/// the job action it belongs to. Traffic coordination decides how far the vehicle may go: the
/// nodes of the actions cleared so far form the base (released), the rest the horizon. Each
/// clearance that lets the vehicle go further makes an order update (§6.6.2): the same order
/// id, the next orderUpdateId, starting at the last base node sent before (the stitching node)
/// so that nothing of the base is sent twice. A value type.
class JobOrder {
 public:
  /// `waypoints` must hold the vehicle's place first (action_index of the first action) and at
  /// least one more; InvalidArgument otherwise.
  static absl::StatusOr<JobOrder> Create(std::string order_id, std::string map_id,
                                         std::vector<OrderWaypoint> waypoints,
                                         JobOrderParams params = {});

  /// The first message (orderUpdateId 0) with actions up to `cleared_up_to_action` released.
  Order First(int cleared_up_to_action);
  /// The update for a clearance that reaches further than the last one, or nullopt when it
  /// releases nothing new.
  std::optional<Order> Release(int cleared_up_to_action);
  /// The message last made, to send again (a vehicle ignores an order it already has: §6.6.4.3).
  const Order& last() const { return last_; }

  const std::string& order_id() const { return order_id_; }
  int action_count() const { return action_count_; }
  size_t node_count() const { return waypoints_.size(); }
  /// The node index of a node's sequence id (nodes are even).
  static size_t NodeIndex(uint32_t sequence_id) { return sequence_id / 2; }
  /// The node where action `action_index` ends.
  size_t EndNodeOf(int action_index) const;
  std::string NodeId(size_t index) const;

 private:
  JobOrder(std::string order_id, std::string map_id, std::vector<OrderWaypoint> waypoints,
           JobOrderParams params);
  /// How many nodes are released for `cleared_up_to_action` (the vehicle's place always).
  size_t ReleasedNodes(int cleared_up_to_action) const;
  /// The message holding the nodes from `from_node` on.
  Order Message(size_t from_node, size_t released_nodes) const;

  std::string order_id_;
  std::string map_id_;
  std::vector<OrderWaypoint> waypoints_;
  JobOrderParams params_;
  int action_count_ = 0;
  uint32_t update_id_ = 0;
  size_t released_nodes_ = 0;  ///< base length of the last message
  Order last_;
};

}  // namespace fleetnav::vda5050
