#include "fleetnav/core/echo_input.hpp"

#include "absl/strings/str_cat.h"

namespace fleetnav {

std::string EchoInput(std::string_view input) {
  if (input.size() <= kMaxEchoedInputBytes) return std::string(input);
  // Room for the suffix within the budget; back up over UTF-8 continuation bytes (10xxxxxx).
  size_t keep = kMaxEchoedInputBytes - 24;
  while (keep > 0 && (static_cast<unsigned char>(input[keep]) & 0xC0) == 0x80) --keep;
  return absl::StrCat(std::string(input.substr(0, keep)), "…(", input.size(), " bytes)");
}

}  // namespace fleetnav
