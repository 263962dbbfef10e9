#include "fleetnav/core/operator_role.hpp"

#include "absl/strings/str_cat.h"
#include "fleetnav/core/echo_input.hpp"

namespace fleetnav {

absl::string_view RoleName(Role role) {
  switch (role) {
    case Role::kViewer:
      return "viewer";
    case Role::kOperator:
      return "operator";
    case Role::kAdmin:
      return "admin";
  }
  return "viewer";
}

absl::StatusOr<Role> ParseRole(absl::string_view text) {
  for (Role role : {Role::kViewer, Role::kOperator, Role::kAdmin}) {
    if (text == RoleName(role)) return role;
  }
  return absl::InvalidArgumentError(
      absl::StrCat("role '", EchoInput(std::string_view(text.data(), text.size())),
                   "' is none of viewer, operator, admin"));
}

}  // namespace fleetnav
