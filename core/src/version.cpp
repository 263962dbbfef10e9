#include "fleetnav/core/version.hpp"

namespace fleetnav {

// FLEETNAV_VERSION is defined for this file only (core/CMakeLists.txt), so a new version
// recompiles one file.
std::string_view Version() { return FLEETNAV_VERSION; }

}  // namespace fleetnav
