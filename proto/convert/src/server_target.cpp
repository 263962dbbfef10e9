#include "fleetnav/proto/server_target.hpp"

#include <arpa/inet.h>

#include <optional>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"

namespace fleetnav {
namespace {

enum class Family { kIpv4, kIpv6, kName };

/// The family of an entry's host ("[::1]:5" is IPv6); *normalized gets the entry as gRPC's
/// list wants it.
Family HostFamily(const std::string& entry, std::string* normalized) {
  *normalized = entry;
  const size_t colon = entry.rfind(':');
  std::string host = colon == std::string::npos ? entry : entry.substr(0, colon);
  if (host == "localhost") {
    *normalized = absl::StrCat("127.0.0.1", entry.substr(colon));
    return Family::kIpv4;
  }
  unsigned char address[16];
  if (inet_pton(AF_INET, host.c_str(), address) == 1) return Family::kIpv4;
  if (host.size() > 2 && host.front() == '[' && host.back() == ']' &&
      inet_pton(AF_INET6, host.substr(1, host.size() - 2).c_str(), address) == 1) {
    return Family::kIpv6;
  }
  return Family::kName;
}

}  // namespace

absl::StatusOr<std::string> ServerTarget(std::string_view servers) {
  const std::string text(servers);
  const bool has_scheme = text.rfind("ipv4:", 0) == 0 || text.rfind("ipv6:", 0) == 0 ||
                          text.rfind("dns:", 0) == 0 || text.rfind("unix:", 0) == 0;
  if (has_scheme || text.find(',') == std::string::npos) {
    if (text.empty()) return absl::InvalidArgumentError("server address: empty");
    return text;
  }
  std::vector<std::string> entries;
  std::optional<Family> family;
  for (const absl::string_view piece : absl::StrSplit(text, ',')) {
    const std::string entry(piece);
    if (entry.empty() || entry.rfind(':') == std::string::npos) {
      return absl::InvalidArgumentError(
          absl::StrCat("server list '", text, "': every entry must be IP:port, got '", entry, "'"));
    }
    std::string normalized;
    const Family entry_family = HostFamily(entry, &normalized);
    if (entry_family == Family::kName) {
      return absl::InvalidArgumentError(
          absl::StrCat("server list '", text, "': '", entry,
                       "' is a host name; a list takes IP addresses (for names give one DNS "
                       "name with several addresses, dns:///NAME:PORT)"));
    }
    if (family && *family != entry_family) {
      return absl::InvalidArgumentError(
          absl::StrCat("server list '", text, "': mixes IPv4 and IPv6 addresses"));
    }
    family = entry_family;
    entries.push_back(normalized);
  }
  return absl::StrCat(*family == Family::kIpv4 ? "ipv4:" : "ipv6:", absl::StrJoin(entries, ","));
}

}  // namespace fleetnav
