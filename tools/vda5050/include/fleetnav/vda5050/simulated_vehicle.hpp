#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "fleetnav/core/pose2.hpp"
#include "fleetnav/vda5050/vda_messages.hpp"

namespace fleetnav::vda5050 {

struct SimulatedVehicleParams {
  std::string manufacturer = "acme";
  std::string serial_number = "0001";
  std::string map_id;
  Pose2 start;
  double speed_mps = 1.0;
  double yaw_rate_radps = 1.0;
  double node_tolerance_m = 0.05;  ///< when a node's allowedDeviationXY is 0
  Factsheet factsheet;             ///< header filled in by the vehicle
};

/// What happened in one step worth telling at once (§6.10: state on every relevant event).
struct VehicleStepEvents {
  bool changed = false;       ///< a node passed, driving started or stopped
  bool first_motion = false;  ///< the order's first movement
  std::string moving_order_id;
};

/// A VDA 5050 2.0 vehicle as the protocol describes its side, for tests and benchmarks: takes
/// orders (§6.6) — a new one only when idle; an update of the running one only with a higher
/// orderUpdateId that starts at its last base node (orderUpdateError otherwise, WARNING, the
/// running order kept; the same update again ignored); a malformed one refused with
/// validationError — drives straight from node to released node at its speed (an omni
/// platform: it turns to a node's theta on the way), and reports each node passed in its state
/// (§6.10.2). Instant actions: cancelOrder, startPause, stopPause, factsheetRequest (§6.8).
/// No network: the caller moves messages. Not thread-safe.
class SimulatedVehicle {
 public:
  explicit SimulatedVehicle(SimulatedVehicleParams params);

  /// An `order` message's payload.
  void OnOrder(const std::string& json);
  /// An `instantActions` payload; returns true when a factsheet was asked for.
  bool OnInstantActions(const std::string& json);
  /// Moves the vehicle dt_s.
  VehicleStepEvents Step(double dt_s, int64_t unix_ms);

  State MakeState(int64_t unix_ms);
  Connection MakeConnection(ConnectionState state, int64_t unix_ms);
  Factsheet MakeFactsheet(int64_t unix_ms);
  const Pose2& pose() const { return pose_; }
  bool driving() const { return driving_; }
  const std::string& order_id() const { return order_id_; }
  /// What the vehicle reports now: refused orders (cleared by the next accepted one).
  const std::vector<VehicleError>& errors() const { return errors_; }

 private:
  void Refuse(const std::string& type, const std::string& why, const std::string& order_id);
  /// This vehicle's header with the next id of the topic `counter` counts (§6.4).
  Header NextHeader(uint32_t* counter, int64_t unix_ms) const;
  /// The next node to reach, if it is released.
  const Node* NextTarget() const;

  SimulatedVehicleParams params_;
  Pose2 pose_;
  std::string order_id_;
  uint32_t order_update_id_ = 0;
  std::vector<Node> nodes_;  ///< still to pass, in order
  std::vector<Edge> edges_;
  std::string last_node_id_;
  uint32_t last_node_sequence_id_ = 0;
  bool driving_ = false;
  bool paused_ = false;
  bool moved_this_order_ = false;
  std::vector<ActionState> action_states_;
  std::vector<VehicleError> errors_;
  uint32_t state_header_id_ = 0;
  uint32_t connection_header_id_ = 0;
  uint32_t factsheet_header_id_ = 0;
};

}  // namespace fleetnav::vda5050
