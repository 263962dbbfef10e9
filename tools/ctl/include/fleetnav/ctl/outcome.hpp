#pragma once

#include <string>

#include "absl/status/status.h"

namespace fleetnav::ctl {

/// fleetnavctl's exit codes, by outcome (docs/binaries.md). Scripts rely on them.
enum class ExitCode : int {
  kOk = 0,
  kJobFailed = 1,  ///< a followed job failed or was cancelled; also any other error
  kUsage = 2,      ///< the command line is wrong
  kNotFound = 3,
  kRefused = 4,      ///< the server refused the input or the state forbids it
  kUnavailable = 5,  ///< the server cannot be reached or did not answer in time
  kDenied = 6,       ///< missing or wrong credentials, or a role without the right
};

/// The exit code of a command that ended with `status`.
ExitCode ExitCodeFor(const absl::Status& status);

/// The one line fleetnavctl prints for a failed command: a connection failure in words ("cannot
/// reach fleetnavd at 127.0.0.1:50051: connection refused — is it running?"), anything else as
/// the status with its code. A connection that opens but never answers is often the wrong
/// security: `tls` (the command used --tls-ca) picks which hint follows.
std::string DescribeFailure(const absl::Status& status, const std::string& server_address,
                            bool tls = false);

}  // namespace fleetnav::ctl
