// Route YAML as operators upload it; what parses is written back and must parse again with as
// many actions.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "fleetnav/core/route.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  absl::StatusOr<fleetnav::Route> route = fleetnav::ParseRouteYaml(text);
  if (!route.ok()) return 0;
  absl::StatusOr<fleetnav::Route> again = fleetnav::ParseRouteYaml(fleetnav::RouteToYaml(*route));
  if (!again.ok() || again->actions.size() != route->actions.size()) std::abort();
  return 0;
}
