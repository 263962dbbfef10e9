#pragma once

#include <string>

#include "absl/status/status.h"

namespace fleetnav {

/// Writes `port` (and a newline) to `path` for whoever started the server and waits for it. The
/// file appears whole or not at all (written beside it, then renamed over it), so a reader never
/// sees part of a number, and a file left by an earlier run is replaced in one step.
absl::Status WritePortFile(const std::string& path, int port);

}  // namespace fleetnav
