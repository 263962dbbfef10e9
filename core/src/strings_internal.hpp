#pragma once

// This abseil build keeps its own absl::string_view (ABSL_OPTION_USE_STD_STRING_VIEW is 0), so
// a std::string_view from the public API must be converted before it meets absl::StrCat.
#include <string_view>

#include "absl/strings/string_view.h"

namespace fleetnav::internal {

inline absl::string_view ToAbsl(std::string_view text) { return {text.data(), text.size()}; }

}  // namespace fleetnav::internal
