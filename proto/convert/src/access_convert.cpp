#include "fleetnav/proto/access_convert.hpp"

#include "absl/strings/str_cat.h"

namespace fleetnav {

v1::OperatorRole ToProto(Role role) {
  switch (role) {
    case Role::kViewer:
      return v1::OPERATOR_ROLE_VIEWER;
    case Role::kOperator:
      return v1::OPERATOR_ROLE_OPERATOR;
    case Role::kAdmin:
      return v1::OPERATOR_ROLE_ADMIN;
  }
  return v1::OPERATOR_ROLE_UNSPECIFIED;
}

absl::StatusOr<Role> FromProto(v1::OperatorRole role) {
  switch (role) {
    case v1::OPERATOR_ROLE_VIEWER:
      return Role::kViewer;
    case v1::OPERATOR_ROLE_OPERATOR:
      return Role::kOperator;
    case v1::OPERATOR_ROLE_ADMIN:
      return Role::kAdmin;
    default:
      return absl::InvalidArgumentError(
          absl::StrCat("role: ", static_cast<int>(role), " is none of viewer, operator, admin"));
  }
}

}  // namespace fleetnav
