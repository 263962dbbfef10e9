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

std::string DescribeFailure(const absl::Status& status, const std::string& server_address,
                            bool tls) {
  const std::string message(status.message());
  const std::string lower = absl::AsciiStrToLower(message);
  const std::string cannot_reach = absl::StrCat("cannot reach fleetnavd at ", server_address, ": ");
  if (status.code() == absl::StatusCode::kUnavailable) {
    if (absl::StrContains(lower, "connection refused")) {
      return absl::StrCat(cannot_reach, "connection refused — is it running?");
    }
    if (absl::StrContains(lower, "dns resolution failed") ||
        absl::StrContains(lower, "name or service not known")) {
      return absl::StrCat(cannot_reach, "the name does not resolve — is it running?");
    }
    if (absl::StrContains(lower, "no route to host")) {
      return absl::StrCat(cannot_reach, "no route to host — is it running?");
    }
    // The port answered the connection but not the call: most often the two ends disagree on
    // TLS, which gRPC reports only as an unavailable server.
    return absl::StrCat(cannot_reach,
                        tls ? "it does not answer over TLS — does it serve TLS, is --tls-ca the CA "
                              "of its certificate, and does the certificate name the address "
                              "(else --tls-server-name)?"
                            : "it does not answer — is it running? (a fleetnavd serving TLS needs "
                              "--tls-ca)");
  }
  if (status.code() == absl::StatusCode::kDeadlineExceeded &&
      absl::StrContains(lower, "deadline exceeded")) {
    return absl::StrCat(cannot_reach, "no answer before the deadline (--timeout-s)");
  }
  return status.ToString();
}

}  // namespace fleetnav::ctl
