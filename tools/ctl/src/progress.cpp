#include "fleetnav/ctl/progress.hpp"

#include <cmath>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace fleetnav::ctl {

std::string ProgressBar(double fraction) {
  const int width = 30;
  const int filled = static_cast<int>(fraction * width + 0.5);
  return absl::StrCat("[", std::string(filled, '#'), std::string(width - filled, '.'), "]",
                      absl::StrFormat(" %3.0f%%", fraction * 100.0));
}

std::string EtaText(int64_t started_unix_ms, int64_t now_unix_ms, double fraction) {
  const int64_t elapsed_ms = now_unix_ms - started_unix_ms;
  if (!(fraction > 0.0 && fraction < 1.0) || elapsed_ms <= 0) return "";
  const auto remaining_s = static_cast<int64_t>(
      std::llround(static_cast<double>(elapsed_ms) * 1e-3 * (1.0 - fraction) / fraction));
  if (remaining_s >= 3600) {
    return absl::StrFormat("ETA %dh%02dm", remaining_s / 3600, (remaining_s % 3600) / 60);
  }
  return absl::StrFormat("ETA %dm%02ds", remaining_s / 60, remaining_s % 60);
}

}  // namespace fleetnav::ctl
