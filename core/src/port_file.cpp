#include "fleetnav/core/port_file.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "absl/strings/str_cat.h"

namespace fleetnav {

absl::Status WritePortFile(const std::string& path, int port) {
  const std::string partial = path + ".partial";
  FILE* f = std::fopen(partial.c_str(), "w");
  if (f == nullptr) {
    return absl::PermissionDeniedError(
        absl::StrCat("cannot write the port file '", partial, "': ", std::strerror(errno)));
  }
  const bool written = std::fprintf(f, "%d\n", port) > 0;
  const bool closed = std::fclose(f) == 0;
  if (!written || !closed || std::rename(partial.c_str(), path.c_str()) != 0) {
    std::remove(partial.c_str());
    return absl::InternalError(absl::StrCat("cannot write the port file '", path, "'"));
  }
  return absl::OkStatus();
}

}  // namespace fleetnav
