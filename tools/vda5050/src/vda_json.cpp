#include "fleetnav/vda5050/vda_json.hpp"

#include <cmath>
#include <ctime>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <regex>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "fleetnav/core/status_macros.hpp"

namespace fleetnav::vda5050 {
namespace {

using Json = nlohmann::json;

/// Reads the fields of one JSON object, naming each by its path and the section of the
/// specification that defines it in every refusal.
class Fields {
 public:
  Fields(const Json& object, std::string path, std::string section)
      : object_(object), path_(std::move(path)), section_(std::move(section)) {}

  static absl::StatusOr<Fields> Of(const Json& value, const std::string& path,
                                   const std::string& section) {
    if (!value.is_object()) {
      return absl::InvalidArgumentError(absl::StrCat(path, ": expected an object (", section, ")"));
    }
    return Fields(value, path, section);
  }

  bool Has(const char* key) const { return object_.contains(key) && !object_[key].is_null(); }
  std::string Path(const char* key) const { return absl::StrCat(path_, ".", key); }
  const std::string& section() const { return section_; }

  absl::Status Missing(const char* key, const char* what) const {
    return absl::InvalidArgumentError(
        absl::StrCat(Path(key), ": required ", what, " (", section_, ")"));
  }
  absl::Status Wrong(const char* key, const std::string& why) const {
    return absl::InvalidArgumentError(absl::StrCat(Path(key), ": ", why, " (", section_, ")"));
  }

  absl::StatusOr<std::string> String(const char* key) const {
    if (!Has(key) || !object_[key].is_string()) return Missing(key, "string");
    return object_[key].get<std::string>();
  }
  absl::StatusOr<std::string> OptionalString(const char* key) const {
    if (!Has(key)) return std::string();
    if (!object_[key].is_string()) return Wrong(key, "must be a string");
    return object_[key].get<std::string>();
  }
  absl::StatusOr<double> Number(const char* key) const {
    if (!Has(key) || !object_[key].is_number()) return Missing(key, "number");
    const double value = object_[key].get<double>();
    if (!std::isfinite(value)) return Wrong(key, "must be finite");
    return value;
  }
  absl::StatusOr<std::optional<double>> OptionalNumber(const char* key) const {
    if (!Has(key)) return std::optional<double>();
    ASSIGN_OR_RETURN(const double value, Number(key));
    return std::optional<double>(value);
  }
  absl::StatusOr<uint32_t> Uint32(const char* key) const {
    if (!Has(key) || !object_[key].is_number_integer()) return Missing(key, "integer");
    const int64_t value = object_[key].get<int64_t>();
    if (value < 0 || value > std::numeric_limits<uint32_t>::max()) {
      return Wrong(key, absl::StrCat("must be a uint32, got ", value));
    }
    return static_cast<uint32_t>(value);
  }
  absl::StatusOr<bool> Bool(const char* key) const {
    if (!Has(key) || !object_[key].is_boolean()) return Missing(key, "boolean (true or false)");
    return object_[key].get<bool>();
  }
  absl::StatusOr<std::optional<bool>> OptionalBool(const char* key) const {
    if (!Has(key)) return std::optional<bool>();
    ASSIGN_OR_RETURN(const bool value, Bool(key));
    return std::optional<bool>(value);
  }
  /// One of `values`, spelt exactly (§6.1.3: enums are upper case).
  template <typename E>
  absl::StatusOr<E> Enum(const char* key,
                         std::initializer_list<std::pair<const char*, E>> values) const {
    ASSIGN_OR_RETURN(const std::string text, String(key));
    std::string known;
    for (const auto& [name, value] : values) {
      if (text == name) return value;
      absl::StrAppend(&known, known.empty() ? "" : ", ", name);
    }
    return Wrong(key, absl::StrCat("'", text, "' is none of ", known));
  }
  /// Each element of the array `key` (required unless `optional`) through `read`.
  absl::Status Array(
      const char* key, bool optional,
      const std::function<absl::Status(const Json&, const std::string&)>& read) const {
    if (!Has(key)) return optional ? absl::OkStatus() : Missing(key, "array");
    if (!object_[key].is_array()) return Wrong(key, "must be an array");
    for (size_t i = 0; i < object_[key].size(); ++i) {
      RETURN_IF_ERROR(read(object_[key][i], absl::StrCat(Path(key), "[", i, "]")));
    }
    return absl::OkStatus();
  }
  const Json& operator[](const char* key) const { return object_[key]; }

 private:
  const Json& object_;
  std::string path_;
  std::string section_;
};

absl::StatusOr<Json> ParseJson(std::string_view text, const char* message) {
  Json json = Json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (json.is_discarded()) {
    return absl::InvalidArgumentError(absl::StrCat(message, ": not JSON"));
  }
  if (!json.is_object()) {
    return absl::InvalidArgumentError(absl::StrCat(message, ": expected a JSON object"));
  }
  return json;
}

/// §6.4: timestamps are ISO 8601 in UTC, "YYYY-MM-DDTHH:mm:ss(.fraction)Z".
bool IsTimestamp(const std::string& text) {
  static const std::regex kPattern(R"(\d{4}-\d{2}-\d{2}T\d{2}:\d{2}:\d{2}(\.\d+)?Z)");
  return std::regex_match(text, kPattern);
}

/// The header (§6.4). `header_id_required`: the factsheet's schema leaves headerId and
/// timestamp out of its required fields (§6.15).
absl::StatusOr<Header> ReadHeader(const Fields& f, bool header_id_required = true) {
  Header header;
  if (header_id_required || f.Has("headerId")) {
    ASSIGN_OR_RETURN(header.header_id, f.Uint32("headerId"));
  }
  if (header_id_required || f.Has("timestamp")) {
    ASSIGN_OR_RETURN(header.timestamp, f.String("timestamp"));
    if (!IsTimestamp(header.timestamp)) {
      return f.Wrong("timestamp", absl::StrCat("'", header.timestamp,
                                               "' is not ISO 8601 UTC (YYYY-MM-DDTHH:mm:ss.ffZ)"));
    }
  }
  ASSIGN_OR_RETURN(header.version, f.String("version"));
  if (header.version.rfind("2.", 0) != 0) {
    return f.Wrong("version", absl::StrCat("'", header.version, "': this bridge speaks 2.x"));
  }
  ASSIGN_OR_RETURN(header.manufacturer, f.String("manufacturer"));
  ASSIGN_OR_RETURN(header.serial_number, f.String("serialNumber"));
  return header;
}

void WriteHeader(const Header& header, Json* json) {
  (*json)["headerId"] = header.header_id;
  (*json)["timestamp"] = header.timestamp;
  (*json)["version"] = header.version;
  (*json)["manufacturer"] = header.manufacturer;
  (*json)["serialNumber"] = header.serial_number;
}

absl::StatusOr<Action> ReadAction(const Json& value, const std::string& path) {
  ASSIGN_OR_RETURN(const Fields f, Fields::Of(value, path, "§6.7"));
  Action action;
  ASSIGN_OR_RETURN(action.action_type, f.String("actionType"));
  ASSIGN_OR_RETURN(action.action_id, f.String("actionId"));
  ASSIGN_OR_RETURN(action.action_description, f.OptionalString("actionDescription"));
  ASSIGN_OR_RETURN(action.blocking_type,
                   f.Enum<BlockingType>("blockingType", {{"NONE", BlockingType::kNone},
                                                         {"SOFT", BlockingType::kSoft},
                                                         {"HARD", BlockingType::kHard}}));
  RETURN_IF_ERROR(f.Array(
      "actionParameters", true, [&](const Json& p, const std::string& where) -> absl::Status {
        ASSIGN_OR_RETURN(const Fields pf, Fields::Of(p, where, "§6.7, §7.2"));
        ASSIGN_OR_RETURN(std::string key, pf.String("key"));
        if (!pf.Has("value")) return pf.Missing("value", "value");
        const Json& v = pf["value"];
        action.parameters.emplace_back(key, v.is_string() ? v.get<std::string>() : v.dump());
        return absl::OkStatus();
      }));
  return action;
}

Json WriteAction(const Action& action) {
  Json json = {{"actionType", action.action_type},
               {"actionId", action.action_id},
               {"blockingType", std::string(BlockingTypeName(action.blocking_type))}};
  if (!action.action_description.empty()) json["actionDescription"] = action.action_description;
  if (!action.parameters.empty()) {
    Json parameters = Json::array();
    for (const auto& [key, value] : action.parameters) {
      parameters.push_back({{"key", key}, {"value", value}});
    }
    json["actionParameters"] = parameters;
  }
  return json;
}

absl::StatusOr<AgvPosition> ReadAgvPosition(const Json& value, const std::string& path) {
  ASSIGN_OR_RETURN(const Fields f, Fields::Of(value, path, "§6.10.6"));
  AgvPosition position;
  ASSIGN_OR_RETURN(position.x_m, f.Number("x"));
  ASSIGN_OR_RETURN(position.y_m, f.Number("y"));
  ASSIGN_OR_RETURN(position.theta_rad, f.Number("theta"));
  ASSIGN_OR_RETURN(position.map_id, f.String("mapId"));
  ASSIGN_OR_RETURN(position.position_initialized, f.Bool("positionInitialized"));
  ASSIGN_OR_RETURN(position.localization_score, f.OptionalNumber("localizationScore"));
  if (position.localization_score &&
      (*position.localization_score < 0.0 || *position.localization_score > 1.0)) {
    return f.Wrong("localizationScore", "must be in [0, 1]");
  }
  return position;
}

Json WriteAgvPosition(const AgvPosition& position) {
  Json json = {{"x", position.x_m},
               {"y", position.y_m},
               {"theta", position.theta_rad},
               {"mapId", position.map_id},
               {"positionInitialized", position.position_initialized}};
  if (position.localization_score) json["localizationScore"] = *position.localization_score;
  return json;
}

absl::StatusOr<Velocity> ReadVelocity(const Json& value, const std::string& path) {
  ASSIGN_OR_RETURN(const Fields f, Fields::Of(value, path, "§6.10.6"));
  Velocity velocity;
  ASSIGN_OR_RETURN(const std::optional<double> vx, f.OptionalNumber("vx"));
  ASSIGN_OR_RETURN(const std::optional<double> vy, f.OptionalNumber("vy"));
  ASSIGN_OR_RETURN(const std::optional<double> omega, f.OptionalNumber("omega"));
  velocity.vx_mps = vx.value_or(0.0);
  velocity.vy_mps = vy.value_or(0.0);
  velocity.omega_radps = omega.value_or(0.0);
  return velocity;
}

Json WriteVelocity(const Velocity& velocity) {
  return {{"vx", velocity.vx_mps}, {"vy", velocity.vy_mps}, {"omega", velocity.omega_radps}};
}

}  // namespace

std::string_view BlockingTypeName(BlockingType type) {
  switch (type) {
    case BlockingType::kNone:
      return "NONE";
    case BlockingType::kSoft:
      return "SOFT";
    case BlockingType::kHard:
      return "HARD";
  }
  return "HARD";
}

std::string_view ActionStatusName(ActionStatus status) {
  switch (status) {
    case ActionStatus::kWaiting:
      return "WAITING";
    case ActionStatus::kInitializing:
      return "INITIALIZING";
    case ActionStatus::kRunning:
      return "RUNNING";
    case ActionStatus::kPaused:
      return "PAUSED";
    case ActionStatus::kFinished:
      return "FINISHED";
    case ActionStatus::kFailed:
      return "FAILED";
  }
  return "FAILED";
}

std::string_view ErrorLevelName(ErrorLevel level) {
  return level == ErrorLevel::kFatal ? "FATAL" : "WARNING";
}

std::string_view OperatingModeName(OperatingMode mode) {
  switch (mode) {
    case OperatingMode::kAutomatic:
      return "AUTOMATIC";
    case OperatingMode::kSemiautomatic:
      return "SEMIAUTOMATIC";
    case OperatingMode::kManual:
      return "MANUAL";
    case OperatingMode::kService:
      return "SERVICE";
    case OperatingMode::kTeachIn:
      return "TEACHIN";
  }
  return "AUTOMATIC";
}

std::string_view ConnectionStateName(ConnectionState state) {
  switch (state) {
    case ConnectionState::kOnline:
      return "ONLINE";
    case ConnectionState::kOffline:
      return "OFFLINE";
    case ConnectionState::kConnectionBroken:
      return "CONNECTIONBROKEN";
  }
  return "OFFLINE";
}

std::string Timestamp(int64_t unix_ms) {
  const std::time_t seconds = static_cast<std::time_t>(unix_ms / 1000);
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  return absl::StrFormat("%04d-%02d-%02dT%02d:%02d:%02d.%03dZ", utc.tm_year + 1900, utc.tm_mon + 1,
                         utc.tm_mday, utc.tm_hour, utc.tm_min, utc.tm_sec,
                         static_cast<int>(unix_ms % 1000));
}

absl::StatusOr<Order> ParseOrder(std::string_view text) {
  ASSIGN_OR_RETURN(const Json json, ParseJson(text, "order"));
  const Fields f(json, "order", "§6.7");
  Order order;
  ASSIGN_OR_RETURN(order.header, ReadHeader(f));
  ASSIGN_OR_RETURN(order.order_id, f.String("orderId"));
  ASSIGN_OR_RETURN(order.order_update_id, f.Uint32("orderUpdateId"));
  RETURN_IF_ERROR(
      f.Array("nodes", false, [&](const Json& value, const std::string& where) -> absl::Status {
        ASSIGN_OR_RETURN(const Fields nf, Fields::Of(value, where, "§6.7"));
        Node node;
        ASSIGN_OR_RETURN(node.node_id, nf.String("nodeId"));
        ASSIGN_OR_RETURN(node.sequence_id, nf.Uint32("sequenceId"));
        ASSIGN_OR_RETURN(node.released, nf.Bool("released"));
        if (nf.Has("nodePosition")) {
          ASSIGN_OR_RETURN(const Fields pf,
                           Fields::Of(nf["nodePosition"], nf.Path("nodePosition"), "§6.7"));
          NodePosition position;
          ASSIGN_OR_RETURN(position.x_m, pf.Number("x"));
          ASSIGN_OR_RETURN(position.y_m, pf.Number("y"));
          ASSIGN_OR_RETURN(position.theta_rad, pf.OptionalNumber("theta"));
          ASSIGN_OR_RETURN(position.map_id, pf.String("mapId"));
          ASSIGN_OR_RETURN(const std::optional<double> xy, pf.OptionalNumber("allowedDeviationXY"));
          if (xy && *xy < 0.0) return pf.Wrong("allowedDeviationXY", "must be >= 0");
          position.allowed_deviation_xy_m = xy.value_or(0.0);
          ASSIGN_OR_RETURN(position.allowed_deviation_theta_rad,
                           pf.OptionalNumber("allowedDeviationTheta"));
          node.position = position;
        }
        RETURN_IF_ERROR(
            nf.Array("actions", false, [&](const Json& a, const std::string& at) -> absl::Status {
              ASSIGN_OR_RETURN(Action action, ReadAction(a, at));
              node.actions.push_back(std::move(action));
              return absl::OkStatus();
            }));
        order.nodes.push_back(std::move(node));
        return absl::OkStatus();
      }));
  RETURN_IF_ERROR(
      f.Array("edges", false, [&](const Json& value, const std::string& where) -> absl::Status {
        ASSIGN_OR_RETURN(const Fields ef, Fields::Of(value, where, "§6.7"));
        Edge edge;
        ASSIGN_OR_RETURN(edge.edge_id, ef.String("edgeId"));
        ASSIGN_OR_RETURN(edge.sequence_id, ef.Uint32("sequenceId"));
        ASSIGN_OR_RETURN(edge.released, ef.Bool("released"));
        ASSIGN_OR_RETURN(edge.start_node_id, ef.String("startNodeId"));
        ASSIGN_OR_RETURN(edge.end_node_id, ef.String("endNodeId"));
        ASSIGN_OR_RETURN(edge.max_speed_mps, ef.OptionalNumber("maxSpeed"));
        RETURN_IF_ERROR(
            ef.Array("actions", false, [&](const Json& a, const std::string& at) -> absl::Status {
              ASSIGN_OR_RETURN(Action action, ReadAction(a, at));
              edge.actions.push_back(std::move(action));
              return absl::OkStatus();
            }));
        order.edges.push_back(std::move(edge));
        return absl::OkStatus();
      }));
  return order;
}

std::string ToJson(const Order& order) {
  Json json;
  WriteHeader(order.header, &json);
  json["orderId"] = order.order_id;
  json["orderUpdateId"] = order.order_update_id;
  json["nodes"] = Json::array();
  for (const Node& node : order.nodes) {
    Json n = {{"nodeId", node.node_id},
              {"sequenceId", node.sequence_id},
              {"released", node.released},
              {"actions", Json::array()}};
    if (node.position) {
      Json p = {{"x", node.position->x_m},
                {"y", node.position->y_m},
                {"mapId", node.position->map_id},
                {"allowedDeviationXY", node.position->allowed_deviation_xy_m}};
      if (node.position->theta_rad) p["theta"] = *node.position->theta_rad;
      if (node.position->allowed_deviation_theta_rad) {
        p["allowedDeviationTheta"] = *node.position->allowed_deviation_theta_rad;
      }
      n["nodePosition"] = p;
    }
    for (const Action& action : node.actions) n["actions"].push_back(WriteAction(action));
    json["nodes"].push_back(n);
  }
  json["edges"] = Json::array();
  for (const Edge& edge : order.edges) {
    Json e = {{"edgeId", edge.edge_id},        {"sequenceId", edge.sequence_id},
              {"released", edge.released},     {"startNodeId", edge.start_node_id},
              {"endNodeId", edge.end_node_id}, {"actions", Json::array()}};
    if (edge.max_speed_mps) e["maxSpeed"] = *edge.max_speed_mps;
    for (const Action& action : edge.actions) e["actions"].push_back(WriteAction(action));
    json["edges"].push_back(e);
  }
  return json.dump();
}

absl::StatusOr<InstantActions> ParseInstantActions(std::string_view text) {
  ASSIGN_OR_RETURN(const Json json, ParseJson(text, "instantActions"));
  const Fields f(json, "instantActions", "§6.9");
  InstantActions message;
  ASSIGN_OR_RETURN(message.header, ReadHeader(f));
  if (!f.Has("actions") && f.Has("instantActions")) {
    return f.Wrong("instantActions", "is the 1.1 name; 2.0 calls the array `actions`");
  }
  RETURN_IF_ERROR(
      f.Array("actions", false, [&](const Json& a, const std::string& at) -> absl::Status {
        ASSIGN_OR_RETURN(Action action, ReadAction(a, at));
        message.actions.push_back(std::move(action));
        return absl::OkStatus();
      }));
  return message;
}

std::string ToJson(const InstantActions& message) {
  Json json;
  WriteHeader(message.header, &json);
  json["actions"] = Json::array();
  for (const Action& action : message.actions) json["actions"].push_back(WriteAction(action));
  return json.dump();
}

absl::StatusOr<State> ParseState(std::string_view text) {
  ASSIGN_OR_RETURN(const Json json, ParseJson(text, "state"));
  const Fields f(json, "state", "§6.10.6");
  State state;
  ASSIGN_OR_RETURN(state.header, ReadHeader(f));
  ASSIGN_OR_RETURN(state.order_id, f.String("orderId"));
  ASSIGN_OR_RETURN(state.order_update_id, f.Uint32("orderUpdateId"));
  ASSIGN_OR_RETURN(state.last_node_id, f.String("lastNodeId"));
  ASSIGN_OR_RETURN(state.last_node_sequence_id, f.Uint32("lastNodeSequenceId"));
  RETURN_IF_ERROR(
      f.Array("nodeStates", false, [&](const Json& v, const std::string& at) -> absl::Status {
        ASSIGN_OR_RETURN(const Fields nf, Fields::Of(v, at, "§6.10.6"));
        NodeState node;
        ASSIGN_OR_RETURN(node.node_id, nf.String("nodeId"));
        ASSIGN_OR_RETURN(node.sequence_id, nf.Uint32("sequenceId"));
        ASSIGN_OR_RETURN(node.released, nf.Bool("released"));
        state.node_states.push_back(std::move(node));
        return absl::OkStatus();
      }));
  RETURN_IF_ERROR(
      f.Array("edgeStates", false, [&](const Json& v, const std::string& at) -> absl::Status {
        ASSIGN_OR_RETURN(const Fields ef, Fields::Of(v, at, "§6.10.6"));
        EdgeState edge;
        ASSIGN_OR_RETURN(edge.edge_id, ef.String("edgeId"));
        ASSIGN_OR_RETURN(edge.sequence_id, ef.Uint32("sequenceId"));
        ASSIGN_OR_RETURN(edge.released, ef.Bool("released"));
        state.edge_states.push_back(std::move(edge));
        return absl::OkStatus();
      }));
  ASSIGN_OR_RETURN(state.driving, f.Bool("driving"));
  ASSIGN_OR_RETURN(state.paused, f.OptionalBool("paused"));
  if (f.Has("agvPosition")) {
    ASSIGN_OR_RETURN(state.agv_position, ReadAgvPosition(f["agvPosition"], f.Path("agvPosition")));
  }
  if (f.Has("velocity")) {
    ASSIGN_OR_RETURN(state.velocity, ReadVelocity(f["velocity"], f.Path("velocity")));
  }
  RETURN_IF_ERROR(
      f.Array("actionStates", false, [&](const Json& v, const std::string& at) -> absl::Status {
        ASSIGN_OR_RETURN(const Fields af, Fields::Of(v, at, "§6.10.6, §6.11"));
        ActionState action;
        ASSIGN_OR_RETURN(action.action_id, af.String("actionId"));
        ASSIGN_OR_RETURN(action.action_type, af.OptionalString("actionType"));
        ASSIGN_OR_RETURN(action.result_description, af.OptionalString("resultDescription"));
        ASSIGN_OR_RETURN(
            action.status,
            af.Enum<ActionStatus>("actionStatus", {{"WAITING", ActionStatus::kWaiting},
                                                   {"INITIALIZING", ActionStatus::kInitializing},
                                                   {"RUNNING", ActionStatus::kRunning},
                                                   {"PAUSED", ActionStatus::kPaused},
                                                   {"FINISHED", ActionStatus::kFinished},
                                                   {"FAILED", ActionStatus::kFailed}}));
        state.action_states.push_back(std::move(action));
        return absl::OkStatus();
      }));
  if (!f.Has("batteryState")) return f.Missing("batteryState", "object");
  ASSIGN_OR_RETURN(const Fields bf,
                   Fields::Of(f["batteryState"], f.Path("batteryState"), "§6.10.6"));
  ASSIGN_OR_RETURN(state.battery_charge_percent, bf.Number("batteryCharge"));
  ASSIGN_OR_RETURN(state.charging, bf.Bool("charging"));
  ASSIGN_OR_RETURN(
      state.operating_mode,
      f.Enum<OperatingMode>("operatingMode", {{"AUTOMATIC", OperatingMode::kAutomatic},
                                              {"SEMIAUTOMATIC", OperatingMode::kSemiautomatic},
                                              {"MANUAL", OperatingMode::kManual},
                                              {"SERVICE", OperatingMode::kService},
                                              {"TEACHIN", OperatingMode::kTeachIn}}));
  RETURN_IF_ERROR(
      f.Array("errors", false, [&](const Json& v, const std::string& at) -> absl::Status {
        ASSIGN_OR_RETURN(const Fields ef, Fields::Of(v, at, "§6.10.5, §6.10.6"));
        VehicleError error;
        ASSIGN_OR_RETURN(error.error_type, ef.String("errorType"));
        ASSIGN_OR_RETURN(error.description, ef.OptionalString("errorDescription"));
        ASSIGN_OR_RETURN(error.level,
                         ef.Enum<ErrorLevel>("errorLevel", {{"WARNING", ErrorLevel::kWarning},
                                                            {"FATAL", ErrorLevel::kFatal}}));
        RETURN_IF_ERROR(ef.Array("errorReferences", true,
                                 [&](const Json& r, const std::string& rat) -> absl::Status {
                                   ASSIGN_OR_RETURN(const Fields rf, Fields::Of(r, rat, "§6.10.6"));
                                   ASSIGN_OR_RETURN(std::string key, rf.String("referenceKey"));
                                   ASSIGN_OR_RETURN(std::string value, rf.String("referenceValue"));
                                   error.references.emplace_back(std::move(key), std::move(value));
                                   return absl::OkStatus();
                                 }));
        state.errors.push_back(std::move(error));
        return absl::OkStatus();
      }));
  if (!f.Has("safetyState")) return f.Missing("safetyState", "object");
  ASSIGN_OR_RETURN(const Fields sf, Fields::Of(f["safetyState"], f.Path("safetyState"), "§6.10.6"));
  ASSIGN_OR_RETURN(state.e_stop, sf.Enum<std::string>("eStop", {{"AUTOACK", "AUTOACK"},
                                                                {"MANUAL", "MANUAL"},
                                                                {"REMOTE", "REMOTE"},
                                                                {"NONE", "NONE"}}));
  ASSIGN_OR_RETURN(state.field_violation, sf.Bool("fieldViolation"));
  return state;
}

std::string ToJson(const State& state) {
  Json json;
  WriteHeader(state.header, &json);
  json["orderId"] = state.order_id;
  json["orderUpdateId"] = state.order_update_id;
  json["lastNodeId"] = state.last_node_id;
  json["lastNodeSequenceId"] = state.last_node_sequence_id;
  json["nodeStates"] = Json::array();
  for (const NodeState& node : state.node_states) {
    json["nodeStates"].push_back(
        {{"nodeId", node.node_id}, {"sequenceId", node.sequence_id}, {"released", node.released}});
  }
  json["edgeStates"] = Json::array();
  for (const EdgeState& edge : state.edge_states) {
    json["edgeStates"].push_back(
        {{"edgeId", edge.edge_id}, {"sequenceId", edge.sequence_id}, {"released", edge.released}});
  }
  json["driving"] = state.driving;
  if (state.paused) json["paused"] = *state.paused;
  if (state.agv_position) json["agvPosition"] = WriteAgvPosition(*state.agv_position);
  if (state.velocity) json["velocity"] = WriteVelocity(*state.velocity);
  json["actionStates"] = Json::array();
  for (const ActionState& action : state.action_states) {
    Json a = {{"actionId", action.action_id},
              {"actionStatus", std::string(ActionStatusName(action.status))}};
    if (!action.action_type.empty()) a["actionType"] = action.action_type;
    if (!action.result_description.empty()) a["resultDescription"] = action.result_description;
    json["actionStates"].push_back(a);
  }
  json["batteryState"] = {{"batteryCharge", state.battery_charge_percent},
                          {"charging", state.charging}};
  json["operatingMode"] = std::string(OperatingModeName(state.operating_mode));
  json["errors"] = Json::array();
  for (const VehicleError& error : state.errors) {
    Json e = {{"errorType", error.error_type},
              {"errorLevel", std::string(ErrorLevelName(error.level))}};
    if (!error.description.empty()) e["errorDescription"] = error.description;
    if (!error.references.empty()) {
      e["errorReferences"] = Json::array();
      for (const auto& [key, value] : error.references) {
        e["errorReferences"].push_back({{"referenceKey", key}, {"referenceValue", value}});
      }
    }
    json["errors"].push_back(e);
  }
  json["safetyState"] = {{"eStop", state.e_stop}, {"fieldViolation", state.field_violation}};
  return json.dump();
}

absl::StatusOr<Visualization> ParseVisualization(std::string_view text) {
  ASSIGN_OR_RETURN(const Json json, ParseJson(text, "visualization"));
  const Fields f(json, "visualization", "§6.13");
  Visualization message;
  ASSIGN_OR_RETURN(message.header, ReadHeader(f));
  if (f.Has("agvPosition")) {
    ASSIGN_OR_RETURN(message.agv_position,
                     ReadAgvPosition(f["agvPosition"], f.Path("agvPosition")));
  }
  if (f.Has("velocity")) {
    ASSIGN_OR_RETURN(message.velocity, ReadVelocity(f["velocity"], f.Path("velocity")));
  }
  return message;
}

std::string ToJson(const Visualization& message) {
  Json json;
  WriteHeader(message.header, &json);
  if (message.agv_position) json["agvPosition"] = WriteAgvPosition(*message.agv_position);
  if (message.velocity) json["velocity"] = WriteVelocity(*message.velocity);
  return json.dump();
}

absl::StatusOr<Connection> ParseConnection(std::string_view text) {
  ASSIGN_OR_RETURN(const Json json, ParseJson(text, "connection"));
  const Fields f(json, "connection", "§6.14");
  Connection message;
  ASSIGN_OR_RETURN(message.header, ReadHeader(f));
  ASSIGN_OR_RETURN(message.state, f.Enum<ConnectionState>(
                                      "connectionState",
                                      {{"ONLINE", ConnectionState::kOnline},
                                       {"OFFLINE", ConnectionState::kOffline},
                                       {"CONNECTIONBROKEN", ConnectionState::kConnectionBroken}}));
  return message;
}

std::string ToJson(const Connection& message) {
  Json json;
  WriteHeader(message.header, &json);
  json["connectionState"] = std::string(ConnectionStateName(message.state));
  return json.dump();
}

absl::StatusOr<Factsheet> ParseFactsheet(std::string_view text) {
  ASSIGN_OR_RETURN(const Json json, ParseJson(text, "factsheet"));
  const Fields f(json, "factsheet", "§6.15");
  Factsheet message;
  ASSIGN_OR_RETURN(message.header, ReadHeader(f, /*header_id_required=*/false));
  if (!f.Has("typeSpecification")) return f.Missing("typeSpecification", "object");
  ASSIGN_OR_RETURN(const Fields tf,
                   Fields::Of(f["typeSpecification"], f.Path("typeSpecification"), "§6.15.1"));
  ASSIGN_OR_RETURN(message.series_name, tf.String("seriesName"));
  ASSIGN_OR_RETURN(
      message.agv_kinematic,
      tf.Enum<std::string>("agvKinematic",
                           {{"DIFF", "DIFF"}, {"OMNI", "OMNI"}, {"THREEWHEEL", "THREEWHEEL"}}));
  ASSIGN_OR_RETURN(message.agv_class, tf.Enum<std::string>("agvClass", {{"FORKLIFT", "FORKLIFT"},
                                                                        {"CONVEYOR", "CONVEYOR"},
                                                                        {"TUGGER", "TUGGER"},
                                                                        {"CARRIER", "CARRIER"}}));
  ASSIGN_OR_RETURN(message.max_load_mass_kg, tf.Number("maxLoadMass"));
  if (!f.Has("physicalParameters")) return f.Missing("physicalParameters", "object");
  ASSIGN_OR_RETURN(const Fields pf,
                   Fields::Of(f["physicalParameters"], f.Path("physicalParameters"), "§6.15.1"));
  ASSIGN_OR_RETURN(message.speed_max_mps, pf.Number("speedMax"));
  ASSIGN_OR_RETURN(message.width_m, pf.Number("width"));
  ASSIGN_OR_RETURN(message.length_m, pf.Number("length"));
  if (!(message.speed_max_mps > 0.0)) return pf.Wrong("speedMax", "must be > 0");
  if (!(message.width_m > 0.0)) return pf.Wrong("width", "must be > 0");
  if (!(message.length_m > 0.0)) return pf.Wrong("length", "must be > 0");
  return message;
}

std::string ToJson(const Factsheet& message) {
  Json json;
  WriteHeader(message.header, &json);
  json["typeSpecification"] = {
      {"seriesName", message.series_name}, {"agvKinematic", message.agv_kinematic},
      {"agvClass", message.agv_class},     {"maxLoadMass", message.max_load_mass_kg},
      {"localizationTypes", {"NATURAL"}},  {"navigationTypes", {"AUTONOMOUS"}}};
  json["physicalParameters"] = {{"speedMin", 0.0},           {"speedMax", message.speed_max_mps},
                                {"accelerationMax", 0.5},    {"decelerationMax", 0.5},
                                {"heightMax", 1.0},          {"width", message.width_m},
                                {"length", message.length_m}};
  json["protocolLimits"] = {{"maxStringLens", Json::object()},
                            {"maxArrayLens", Json::object()},
                            {"timing", {{"minOrderInterval", 0.1}, {"minStateInterval", 0.05}}}};
  json["protocolFeatures"] = {
      {"optionalParameters", Json::array()},
      {"agvActions",
       {{{"actionType", "cancelOrder"}, {"actionScopes", {"INSTANT"}}},
        {{"actionType", "startPause"}, {"actionScopes", {"INSTANT"}}},
        {{"actionType", "stopPause"}, {"actionScopes", {"INSTANT"}}},
        {{"actionType", "factsheetRequest"}, {"actionScopes", {"INSTANT"}}}}}};
  json["agvGeometry"] = Json::object();
  json["loadSpecification"] = Json::object();
  return json.dump();
}

}  // namespace fleetnav::vda5050
