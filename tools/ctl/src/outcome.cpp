#include "fleetnav/ctl/outcome.hpp"

#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"

namespace fleetnav::ctl {

ExitCode ExitCodeFor(const absl::Status& status) {
  switch (status.code()) {
    case absl::StatusCode::kOk:
      return ExitCode::kOk;
    case absl::StatusCode::kNotFound:
      return ExitCode::kNotFound;
    case absl::StatusCode::kInvalidArgument:
    case absl::StatusCode::kFailedPrecondition:
    case absl::StatusCode::kAlreadyExists:
    case absl::StatusCode::kOutOfRange:
    case absl::StatusCode::kResourceExhausted:
      return ExitCode::kRefused;
    case absl::StatusCode::kUnavailable:
    case absl::StatusCode::kDeadlineExceeded:
      return ExitCode::kUnavailable;
    case absl::StatusCode::kUnauthenticated:
    case absl::StatusCode::kPermissionDenied:
      return ExitCode::kDenied;
    default:
      return ExitCode::kJobFailed;
  }
}

std::string DescribeFailure(const absl::Status& status, const std::string& server_address) {
  const std::string message(status.message());
  const std::string lower = absl::AsciiStrToLower(message);
  const std::string cannot_reach = absl::StrCat("cannot reach fleetnavd at ", server_address, ": ");
  if (status.code() == absl::StatusCode::kUnavailable) {
    std::string why = "it does not answer";
    if (absl::StrContains(lower, "connection refused")) {
      why = "connection refused";
    } else if (absl::StrContains(lower, "dns resolution failed") ||
               absl::StrContains(lower, "name or service not known")) {
      why = "the name does not resolve";
    } else if (absl::StrContains(lower, "no route to host")) {
      why = "no route to host";
    }
    return absl::StrCat(cannot_reach, why, " — is it running?");
  }
  if (status.code() == absl::StatusCode::kDeadlineExceeded &&
      absl::StrContains(lower, "deadline exceeded")) {
    return absl::StrCat(cannot_reach, "no answer before the deadline (--timeout-s)");
  }
  return status.ToString();
}

}  // namespace fleetnav::ctl
