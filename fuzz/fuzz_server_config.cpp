// fleetnavd's configuration file.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fleetnav/server/rpc/fleet_server_config.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  (void)fleetnav::server::ParseFleetServerConfig(
      std::string(reinterpret_cast<const char*>(data), size));
  return 0;
}
