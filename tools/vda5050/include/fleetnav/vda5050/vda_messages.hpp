#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace fleetnav::vda5050 {

/// The protocol version this bridge speaks (VDA 5050 §6.4: "[Major].[Minor].[Patch]").
inline constexpr std::string_view kProtocolVersion = "2.0.0";

/// The header every message starts with, at the top level of its JSON (§6.4). `header_id`
/// counts the messages of one topic of one sender.
struct Header {
  uint32_t header_id = 0;
  std::string timestamp;  ///< ISO 8601 UTC, e.g. "2017-04-15T11:40:03.12Z"
  std::string version = std::string(kProtocolVersion);
  std::string manufacturer;
  std::string serial_number;
};

/// §6.7 blockingType: NONE runs beside driving, SOFT stops driving, HARD runs alone.
enum class BlockingType { kNone, kSoft, kHard };

/// An action of a node or edge, or an instant action (§6.7; key/value parameters §7.2). Only
/// string, number and boolean parameter values are kept (as text).
struct Action {
  std::string action_type;
  std::string action_id;
  std::string action_description;
  BlockingType blocking_type = BlockingType::kHard;
  std::vector<std::pair<std::string, std::string>> parameters;
};

/// §6.7 nodePosition, metres and radians in the map `map_id`.
struct NodePosition {
  double x_m = 0.0;
  double y_m = 0.0;
  std::optional<double> theta_rad;
  double allowed_deviation_xy_m = 0.0;  ///< 0: the vehicle's own tolerance
  std::optional<double> allowed_deviation_theta_rad;
  std::string map_id;
};

/// §6.7 node: sequence ids run over nodes and edges together (nodes 0, 2, 4 …, edges 1, 3 …).
struct Node {
  std::string node_id;
  uint32_t sequence_id = 0;
  bool released = false;
  std::optional<NodePosition> position;
  std::vector<Action> actions;
};

/// §6.7 edge between two nodes.
struct Edge {
  std::string edge_id;
  uint32_t sequence_id = 0;
  bool released = false;
  std::string start_node_id;
  std::string end_node_id;
  std::optional<double> max_speed_mps;
  std::vector<Action> actions;
};

/// §6.6–6.7 topic `order`: the released nodes and edges are the base, the others the horizon.
/// An update keeps `order_id`, raises `order_update_id` and starts at the last base node.
struct Order {
  Header header;
  std::string order_id;
  uint32_t order_update_id = 0;
  std::vector<Node> nodes;
  std::vector<Edge> edges;
};

/// §6.9 topic `instantActions` (the array is `actions` in 2.0; `instantActions` in 1.1).
struct InstantActions {
  Header header;
  std::vector<Action> actions;
};

/// §6.11 Table 1.
enum class ActionStatus { kWaiting, kInitializing, kRunning, kPaused, kFinished, kFailed };

struct ActionState {
  std::string action_id;
  std::string action_type;
  ActionStatus status = ActionStatus::kWaiting;
  std::string result_description;
};

/// §6.10.6 agvPosition.
struct AgvPosition {
  double x_m = 0.0;
  double y_m = 0.0;
  double theta_rad = 0.0;
  std::string map_id;
  bool position_initialized = false;
  std::optional<double> localization_score;
};

/// §6.10.6 velocity, in the vehicle frame.
struct Velocity {
  double vx_mps = 0.0;
  double vy_mps = 0.0;
  double omega_radps = 0.0;
};

/// §6.10.6 nodeState / edgeState: what is still to be traversed.
struct NodeState {
  std::string node_id;
  uint32_t sequence_id = 0;
  bool released = false;
};
struct EdgeState {
  std::string edge_id;
  uint32_t sequence_id = 0;
  bool released = false;
};

/// §6.10.5: WARNING clears itself or lets the vehicle go on; FATAL needs a person.
enum class ErrorLevel { kWarning, kFatal };

struct VehicleError {
  std::string error_type;  ///< e.g. validationError, orderError, orderUpdateError (§6.6.4)
  std::string description;
  ErrorLevel level = ErrorLevel::kWarning;
  std::vector<std::pair<std::string, std::string>> references;
};

/// §6.10.6 operatingMode.
enum class OperatingMode { kAutomatic, kSemiautomatic, kManual, kService, kTeachIn };

/// §6.10 topic `state`.
struct State {
  Header header;
  std::string order_id;
  uint32_t order_update_id = 0;
  std::string last_node_id;
  uint32_t last_node_sequence_id = 0;
  std::vector<NodeState> node_states;
  std::vector<EdgeState> edge_states;
  bool driving = false;
  std::optional<bool> paused;
  std::optional<AgvPosition> agv_position;
  std::optional<Velocity> velocity;
  std::vector<ActionState> action_states;
  double battery_charge_percent = 100.0;
  bool charging = false;
  OperatingMode operating_mode = OperatingMode::kAutomatic;
  std::vector<VehicleError> errors;
  std::string e_stop = "NONE";  ///< §6.10.6 safetyState.eStop: AUTOACK, MANUAL, REMOTE, NONE
  bool field_violation = false;
};

/// §6.13 topic `visualization`: position and velocity only, every field optional.
struct Visualization {
  Header header;
  std::optional<AgvPosition> agv_position;
  std::optional<Velocity> velocity;
};

/// §6.14 connectionState.
enum class ConnectionState { kOnline, kOffline, kConnectionBroken };

/// §6.14 topic `connection` (published retained; the broken state is the vehicle's last will).
struct Connection {
  Header header;
  ConnectionState state = ConnectionState::kOnline;
};

/// §6.15 topic `factsheet`, the parts the bridge uses: kinematics and size.
struct Factsheet {
  Header header;
  std::string series_name;
  std::string agv_kinematic;  ///< DIFF, OMNI, THREEWHEEL
  std::string agv_class;      ///< FORKLIFT, CONVEYOR, TUGGER, CARRIER
  double max_load_mass_kg = 0.0;
  double speed_max_mps = 0.0;
  double width_m = 0.0;
  double length_m = 0.0;
};

std::string_view BlockingTypeName(BlockingType type);
std::string_view ActionStatusName(ActionStatus status);
std::string_view ErrorLevelName(ErrorLevel level);
std::string_view OperatingModeName(OperatingMode mode);
std::string_view ConnectionStateName(ConnectionState state);

}  // namespace fleetnav::vda5050
