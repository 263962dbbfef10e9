// Marker YAML as operators upload it; what parses is written back and must parse again with as
// many markers.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "fleetnav/core/stripe_marker.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  absl::StatusOr<fleetnav::MarkerSet> markers = fleetnav::ParseMarkerSetYaml(text);
  if (!markers.ok()) return 0;
  absl::StatusOr<fleetnav::MarkerSet> again =
      fleetnav::ParseMarkerSetYaml(fleetnav::MarkerSetToYaml(*markers));
  if (!again.ok() || again->markers.size() != markers->markers.size()) std::abort();
  return 0;
}
