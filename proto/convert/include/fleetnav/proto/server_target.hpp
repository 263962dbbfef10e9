#pragma once

#include <string>
#include <string_view>

#include "absl/status/statusor.h"

namespace fleetnav {

/// fleetnavd's address as a gRPC channel target. One "host:port", or a gRPC target with its
/// scheme such as "dns:///fleet.example:50051" (whose several addresses a client tries in
/// turn) or "ipv4:a:p,b:p", stays as it is. A comma-separated list of "IP:port"s (fleetnavd
/// replicas; "localhost" counts as 127.0.0.1) becomes gRPC's address list, "ipv4:a:p,b:p" or
/// "ipv6:[a]:p,[b]:p": a client takes the first that answers and, when it dies, the next.
/// InvalidArgument for an empty entry, a list with a host name (give one DNS name with several
/// addresses instead) or one mixing IPv4 and IPv6.
absl::StatusOr<std::string> ServerTarget(std::string_view servers);

}  // namespace fleetnav
