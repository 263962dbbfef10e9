#pragma once

#include <string>
#include <string_view>

#include "absl/status/statusor.h"
#include "fleetnav/vda5050/vda_messages.hpp"

namespace fleetnav::vda5050 {

/// Reading and writing VDA 5050 2.0 messages as JSON. Each Parse checks the message against the
/// protocol's schema as written in the specification: required fields and their JSON types,
/// enums spelt exactly, uint32 ranges, the header's version ("2.x.y") and timestamp (ISO 8601
/// UTC, "Z"); a message that fails is InvalidArgument naming the field and the section that
/// defines it (e.g. "state.agvPosition.theta: required number (§6.10.6)"). Fields the bridge
/// does not use are allowed and ignored, as the specification asks (§6.1.1). Each ToJson writes
/// a message that its Parse accepts.
absl::StatusOr<Order> ParseOrder(std::string_view json);
absl::StatusOr<InstantActions> ParseInstantActions(std::string_view json);
absl::StatusOr<State> ParseState(std::string_view json);
absl::StatusOr<Visualization> ParseVisualization(std::string_view json);
absl::StatusOr<Connection> ParseConnection(std::string_view json);
absl::StatusOr<Factsheet> ParseFactsheet(std::string_view json);

std::string ToJson(const Order& order);
std::string ToJson(const InstantActions& actions);
std::string ToJson(const State& state);
std::string ToJson(const Visualization& visualization);
std::string ToJson(const Connection& connection);
std::string ToJson(const Factsheet& factsheet);

/// `unix_ms` as the protocol's timestamp, "2026-11-26T05:40:03.120Z" (§6.4).
std::string Timestamp(int64_t unix_ms);

}  // namespace fleetnav::vda5050
