# FLEETNAV_SANITIZE: empty (default), "address,undefined" or "thread". Every target, fleetnav's
# and the generated gRPC code, is then built and linked with those sanitizers; any report aborts
# the test (no recovery). `make sanitize` and `make tsan` use it in build directories of their own.
set(FLEETNAV_SANITIZE "" CACHE STRING "sanitizers to build with: address,undefined or thread")
if(FLEETNAV_SANITIZE)
  add_compile_options(-fsanitize=${FLEETNAV_SANITIZE} -fno-sanitize-recover=all
    -fno-omit-frame-pointer)
  add_link_options(-fsanitize=${FLEETNAV_SANITIZE})
endif()
