// VDA 5050 2.0 messages as JSON: what the specification requires is checked and refusals name
// the field and the section; what the bridge writes reads back the same.
#include "fleetnav/vda5050/vda_json.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

namespace fleetnav::vda5050 {
namespace {

using ::testing::HasSubstr;

/// A state as a vehicle sends it (§6.10.6), every required field present.
nlohmann::json ValidState() {
  return nlohmann::json::parse(R"({
    "headerId": 7, "timestamp": "2026-11-26T05:40:03.12Z", "version": "2.0.0",
    "manufacturer": "acme", "serialNumber": "0001",
    "orderId": "job-1", "orderUpdateId": 0, "lastNodeId": "job-1-n0", "lastNodeSequenceId": 0,
    "nodeStates": [{"nodeId": "job-1-n1", "sequenceId": 2, "released": true}],
    "edgeStates": [{"edgeId": "job-1-e0", "sequenceId": 1, "released": true}],
    "driving": true,
    "agvPosition": {"x": 1.5, "y": -2.0, "theta": 0.5, "mapId": "store",
                    "positionInitialized": true, "localizationScore": 0.9},
    "velocity": {"vx": 0.8},
    "actionStates": [{"actionId": "a1", "actionStatus": "PAUSED"}],
    "batteryState": {"batteryCharge": 80.5, "charging": false},
    "operatingMode": "AUTOMATIC",
    "errors": [{"errorType": "orderUpdateError", "errorLevel": "WARNING",
                "errorReferences": [{"referenceKey": "orderId", "referenceValue": "job-1"}]}],
    "safetyState": {"eStop": "NONE", "fieldViolation": false},
    "somethingNewer": {"ignored": true}
  })");
}

TEST(VdaJsonTest, AValidStateIsReadWithEveryField) {
  absl::StatusOr<State> state = ParseState(ValidState().dump());
  ASSERT_TRUE(state.ok()) << state.status();
  EXPECT_EQ(state->header.header_id, 7u);
  EXPECT_EQ(state->header.serial_number, "0001");
  EXPECT_EQ(state->last_node_id, "job-1-n0");
  ASSERT_EQ(state->node_states.size(), 1u);
  EXPECT_EQ(state->node_states[0].sequence_id, 2u);
  EXPECT_TRUE(state->driving);
  ASSERT_TRUE(state->agv_position.has_value());
  EXPECT_DOUBLE_EQ(state->agv_position->x_m, 1.5);
  EXPECT_DOUBLE_EQ(*state->agv_position->localization_score, 0.9);
  EXPECT_DOUBLE_EQ(state->velocity->vx_mps, 0.8);
  EXPECT_EQ(state->action_states[0].status, ActionStatus::kPaused);
  EXPECT_DOUBLE_EQ(state->battery_charge_percent, 80.5);
  ASSERT_EQ(state->errors.size(), 1u);
  EXPECT_EQ(state->errors[0].references[0].second, "job-1");
}

TEST(VdaJsonTest, MalformedStatesAreRefusedNamingTheFieldAndSection) {
  struct Case {
    const char* json_pointer;  ///< the field to change
    nlohmann::json value;      ///< null: remove it
    const char* message;
  };
  const Case cases[] = {
      {"/agvPosition/theta", nullptr, "state.agvPosition.theta: required number (§6.10.6)"},
      {"/driving", "yes", "state.driving: required boolean"},
      {"/operatingMode", "automatic", "state.operatingMode: 'automatic' is none of AUTOMATIC"},
      {"/headerId", -1, "state.headerId: must be a uint32, got -1"},
      {"/timestamp", "2026-11-26 05:40:03", "is not ISO 8601 UTC"},
      {"/version", "1.1.0", "this bridge speaks 2.x"},
      {"/batteryState", nullptr, "state.batteryState: required object (§6.10.6)"},
      {"/errors/0/errorLevel", "ERROR", "'ERROR' is none of WARNING, FATAL"},
      {"/nodeStates/0/sequenceId", 2.5, "state.nodeStates[0].sequenceId: required integer"},
      {"/actionStates/0/actionStatus", "DONE", "is none of WAITING, INITIALIZING"},
      {"/safetyState/eStop", "OFF", "state.safetyState.eStop"},
      {"/agvPosition/localizationScore", 1.5, "must be in [0, 1]"},
  };
  for (const Case& c : cases) {
    nlohmann::json state = ValidState();
    const nlohmann::json::json_pointer pointer(c.json_pointer);
    if (c.value.is_null()) {
      state[pointer.parent_pointer()].erase(pointer.back());
    } else {
      state[pointer] = c.value;
    }
    const absl::StatusOr<State> parsed = ParseState(state.dump());
    EXPECT_EQ(parsed.status().code(), absl::StatusCode::kInvalidArgument) << c.json_pointer;
    EXPECT_THAT(parsed.status().message(), HasSubstr(c.message)) << c.json_pointer;
  }
  EXPECT_THAT(ParseState("{\"headerId\": 1").status().message(), HasSubstr("not JSON"));
  EXPECT_THAT(ParseState("[1, 2]").status().message(), HasSubstr("expected a JSON object"));
}

TEST(VdaJsonTest, AnOrderWrittenByTheBridgeReadsBackTheSame) {
  Order order;
  order.header = {3, "2026-11-26T05:40:03.120Z", "2.0.0", "acme", "0001"};
  order.order_id = "job-000001-17";
  order.order_update_id = 2;
  for (uint32_t i = 0; i < 3; ++i) {
    Node node;
    node.node_id = "n" + std::to_string(i);
    node.sequence_id = 2 * i;
    node.released = i < 2;
    node.position =
        NodePosition{1.0 * i, -1.0,         i == 2 ? std::optional<double>(1.57) : std::nullopt,
                     0.5,     std::nullopt, "store"};
    order.nodes.push_back(node);
    if (i < 2) {
      Edge edge;
      edge.edge_id = "e" + std::to_string(i);
      edge.sequence_id = 2 * i + 1;
      edge.released = i < 1;
      edge.start_node_id = node.node_id;
      edge.end_node_id = "n" + std::to_string(i + 1);
      order.edges.push_back(edge);
    }
  }
  absl::StatusOr<Order> read = ParseOrder(ToJson(order));
  ASSERT_TRUE(read.ok()) << read.status();
  EXPECT_EQ(read->order_id, order.order_id);
  EXPECT_EQ(read->order_update_id, 2u);
  ASSERT_EQ(read->nodes.size(), 3u);
  EXPECT_EQ(read->nodes[2].sequence_id, 4u);
  EXPECT_FALSE(read->nodes[2].released);
  EXPECT_DOUBLE_EQ(*read->nodes[2].position->theta_rad, 1.57);
  EXPECT_FALSE(read->nodes[1].position->theta_rad.has_value());
  ASSERT_EQ(read->edges.size(), 2u);
  EXPECT_EQ(read->edges[1].end_node_id, "n2");
  EXPECT_FALSE(read->edges[1].released);
  // Every node and edge carries its actions array, as §6.7 requires.
  const nlohmann::json json = nlohmann::json::parse(ToJson(order));
  EXPECT_TRUE(json["nodes"][0]["actions"].is_array());
  EXPECT_TRUE(json["edges"][0]["actions"].is_array());
}

TEST(VdaJsonTest, InstantActionsUseThe20ArrayNameAndBlockingTypes) {
  InstantActions message;
  message.header = {1, "2026-11-26T05:40:03.120Z", "2.0.0", "acme", "0001"};
  message.actions.push_back({"cancelOrder", "fleetnav-1", "", BlockingType::kHard, {}});
  const std::string json = ToJson(message);
  EXPECT_THAT(json, HasSubstr("\"actions\""));
  absl::StatusOr<InstantActions> read = ParseInstantActions(json);
  ASSERT_TRUE(read.ok()) << read.status();
  EXPECT_EQ(read->actions[0].action_type, "cancelOrder");
  EXPECT_EQ(read->actions[0].blocking_type, BlockingType::kHard);
  // The 1.1 name is refused with the reason.
  nlohmann::json old = nlohmann::json::parse(json);
  old["instantActions"] = old["actions"];
  old.erase("actions");
  EXPECT_THAT(ParseInstantActions(old.dump()).status().message(), HasSubstr("1.1 name"));
}

TEST(VdaJsonTest, ConnectionAndFactsheet) {
  Connection connection;
  connection.header = {0, "2026-11-26T05:40:03.120Z", "2.0.0", "acme", "0001"};
  connection.state = ConnectionState::kConnectionBroken;
  absl::StatusOr<Connection> read = ParseConnection(ToJson(connection));
  ASSERT_TRUE(read.ok()) << read.status();
  EXPECT_EQ(read->state, ConnectionState::kConnectionBroken);
  nlohmann::json bad = nlohmann::json::parse(ToJson(connection));
  bad["connectionState"] = "DISCONNECTED";
  EXPECT_THAT(ParseConnection(bad.dump()).status().message(),
              HasSubstr("connection.connectionState: 'DISCONNECTED' is none of ONLINE"));

  Factsheet factsheet;
  factsheet.header = {0, "2026-11-26T05:40:03.120Z", "2.0.0", "acme", "0001"};
  factsheet.series_name = "sim";
  factsheet.agv_kinematic = "OMNI";
  factsheet.agv_class = "CARRIER";
  factsheet.speed_max_mps = 1.0;
  factsheet.width_m = 0.45;
  factsheet.length_m = 0.75;
  absl::StatusOr<Factsheet> sheet = ParseFactsheet(ToJson(factsheet));
  ASSERT_TRUE(sheet.ok()) << sheet.status();
  EXPECT_EQ(sheet->agv_kinematic, "OMNI");
  EXPECT_DOUBLE_EQ(sheet->length_m, 0.75);
  nlohmann::json no_size = nlohmann::json::parse(ToJson(factsheet));
  no_size["physicalParameters"].erase("width");
  EXPECT_THAT(ParseFactsheet(no_size.dump()).status().message(),
              HasSubstr("factsheet.physicalParameters.width: required number (§6.15.1)"));
  // The factsheet's schema does not require headerId (§6.15).
  nlohmann::json no_id = nlohmann::json::parse(ToJson(factsheet));
  no_id.erase("headerId");
  EXPECT_TRUE(ParseFactsheet(no_id.dump()).ok());
}

TEST(VdaJsonTest, TimestampsAreIso8601Utc) {
  EXPECT_EQ(Timestamp(0), "1970-01-01T00:00:00.000Z");
  EXPECT_EQ(Timestamp(1795671950804), "2026-11-26T05:45:50.804Z");
}

}  // namespace
}  // namespace fleetnav::vda5050
