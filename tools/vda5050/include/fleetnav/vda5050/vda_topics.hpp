#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace fleetnav::vda5050 {

/// A VDA 5050 topic, interfaceName/majorVersion/manufacturer/serialNumber/topic (§6.3), e.g.
/// uagv/v2/acme/0001/state.
struct VehicleTopic {
  std::string interface_name;
  std::string manufacturer;
  std::string serial_number;
  std::string topic;  ///< order, instantActions, state, visualization, connection, factsheet
};

/// The topic's five levels, or nullopt when it has not five or its version is not v2.
std::optional<VehicleTopic> ParseTopic(std::string_view topic);
/// interface/v2/manufacturer/serial/topic.
std::string TopicFor(std::string_view interface_name, std::string_view manufacturer,
                     std::string_view serial_number, std::string_view topic);
/// The fleetnav robot id of a vehicle: "vda-" + manufacturer + "-" + serial number, with every
/// character outside [A-Za-z0-9_.-] replaced by '_' and cut to 64 characters.
std::string RobotIdFor(std::string_view manufacturer, std::string_view serial_number);

}  // namespace fleetnav::vda5050
