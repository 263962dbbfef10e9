// Simulator world files: any text through the world parser (which checks the world too).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fleetnav/sim/world_description.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  (void)fleetnav::sim::ParseWorldYaml(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}
