#pragma once

#include <string_view>

namespace fleetnav {

/// fleetnav's release: the project version of CMakeLists.txt, printed by every binary's
/// --version.
std::string_view Version();

}  // namespace fleetnav
