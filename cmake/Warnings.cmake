# Warning flags for fleetnav's own targets (not for generated code).
add_library(fleetnav_warnings INTERFACE)
target_compile_options(fleetnav_warnings INTERFACE -Wall -Wextra -Wpedantic -Wno-missing-field-initializers)
if(FLEETNAV_WERROR)
  target_compile_options(fleetnav_warnings INTERFACE -Werror)
endif()
