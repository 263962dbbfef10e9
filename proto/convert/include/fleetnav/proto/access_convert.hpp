#pragma once

#include "absl/status/statusor.h"
#include "fleetnav/core/operator_role.hpp"
#include "fleetnav/v1/access_service.pb.h"

namespace fleetnav {

/// Wire <-> domain for operator roles; FromProto refuses UNSPECIFIED and unknown values,
/// naming them.
v1::OperatorRole ToProto(Role role);
absl::StatusOr<Role> FromProto(v1::OperatorRole role);

}  // namespace fleetnav
