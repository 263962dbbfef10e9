#pragma once

#include "absl/status/status.h"
#include "absl/status/statusor.h"

/// Early-return helpers for absl::Status / absl::StatusOr, used across every library boundary.
#define FLEETNAV_CONCAT_INNER(a, b) a##b
#define FLEETNAV_CONCAT(a, b) FLEETNAV_CONCAT_INNER(a, b)

#define RETURN_IF_ERROR(expr)                                                                    \
  do {                                                                                           \
    if (absl::Status _fleetnav_status = (expr); !_fleetnav_status.ok()) return _fleetnav_status; \
  } while (0)

#define ASSIGN_OR_RETURN_IMPL(tmp, lhs, expr)    \
  auto tmp = (expr);                             \
  if (!tmp.ok()) return std::move(tmp).status(); \
  lhs = std::move(tmp).value()

#define ASSIGN_OR_RETURN(lhs, expr) \
  ASSIGN_OR_RETURN_IMPL(FLEETNAV_CONCAT(_fleetnav_statusor_, __LINE__), lhs, expr)
