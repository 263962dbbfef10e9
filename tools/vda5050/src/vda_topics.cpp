#include "fleetnav/vda5050/vda_topics.hpp"

#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"

namespace fleetnav::vda5050 {

std::optional<VehicleTopic> ParseTopic(std::string_view topic) {
  const std::vector<std::string> levels = absl::StrSplit(std::string(topic), '/');
  if (levels.size() != 5 || levels[1] != "v2") return std::nullopt;
  for (const std::string& level : levels) {
    if (level.empty()) return std::nullopt;
  }
  return VehicleTopic{levels[0], levels[2], levels[3], levels[4]};
}

std::string TopicFor(std::string_view interface_name, std::string_view manufacturer,
                     std::string_view serial_number, std::string_view topic) {
  return absl::StrCat(std::string(interface_name), "/v2/", std::string(manufacturer), "/",
                      std::string(serial_number), "/", std::string(topic));
}

std::string RobotIdFor(std::string_view manufacturer, std::string_view serial_number) {
  std::string id = absl::StrCat("vda-", std::string(manufacturer), "-", std::string(serial_number));
  for (char& c : id) {
    const bool allowed = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                         (c >= '0' && c <= '9') || c == '_' || c == '.' || c == '-';
    if (!allowed) c = '_';
  }
  if (id.size() > 64) id.resize(64);
  return id;
}

}  // namespace fleetnav::vda5050
