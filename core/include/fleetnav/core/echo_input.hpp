#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace fleetnav {

/// The most bytes of client-supplied text an error message repeats.
inline constexpr size_t kMaxEchoedInputBytes = 128;

/// Client-supplied text as an error message may repeat it: the text itself when it has at most
/// kMaxEchoedInputBytes bytes, else its first bytes (cut on a UTF-8 character boundary) followed
/// by "…(N bytes)". A 100 kB id echoed whole would push the message past gRPC's metadata limit
/// and turn the client's NOT_FOUND into RESOURCE_EXHAUSTED.
std::string EchoInput(std::string_view input);

}  // namespace fleetnav
