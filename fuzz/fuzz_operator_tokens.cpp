// fleetnavd's operator token table.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fleetnav/server/rpc/server_security.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  (void)fleetnav::server::ParseOperatorTokens(
      std::string(reinterpret_cast<const char*>(data), size));
  return 0;
}
