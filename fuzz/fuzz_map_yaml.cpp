// map_server YAML as operators upload it; what parses is written back and must parse again.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "fleetnav/core/map_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  absl::StatusOr<fleetnav::MapServerMetadata> metadata = fleetnav::ParseMapServerYaml(text);
  if (metadata.ok() &&
      !fleetnav::ParseMapServerYaml(fleetnav::MapServerYamlToString(*metadata)).ok()) {
    std::abort();  // what fleetnav writes it must read
  }
  return 0;
}
