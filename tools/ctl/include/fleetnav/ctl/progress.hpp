#pragma once

#include <cstdint>
#include <string>

namespace fleetnav::ctl {

/// A 30-character bar and the percentage: "[###############...............]  50%".
std::string ProgressBar(double fraction);

/// The time still needed at the pace so far, from the job's start and the stamp of its latest
/// progress (both in the server's milliseconds, simulated ones in a simulated run): "ETA 1m05s",
/// or "" before any progress or at the end.
std::string EtaText(int64_t started_unix_ms, int64_t now_unix_ms, double fraction);

}  // namespace fleetnav::ctl
