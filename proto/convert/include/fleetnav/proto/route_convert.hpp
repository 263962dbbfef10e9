#pragma once

#include "absl/status/statusor.h"
#include "fleetnav/core/route.hpp"
#include "fleetnav/v1/types.pb.h"

namespace fleetnav {

/// Wire <-> domain for routes. FromProto refuses an action with no type, unknown enum values
/// and non-finite numbers, naming `actions[i]`, then runs Route::Validate().
v1::Route ToProto(const Route& route);
absl::StatusOr<Route> FromProto(const v1::Route& route);

}  // namespace fleetnav
