# FLEETNAV_SANITIZE: empty (default) or a -fsanitize= list such as "address,undefined". Every
# target, fleetnav's and the generated gRPC code, is then built and linked with those
# sanitizers; any report aborts the test (no recovery). `make sanitize` uses it in build-asan/.
set(FLEETNAV_SANITIZE "" CACHE STRING "sanitizers to build with, e.g. address,undefined")
if(FLEETNAV_SANITIZE)
  add_compile_options(-fsanitize=${FLEETNAV_SANITIZE} -fno-sanitize-recover=all
    -fno-omit-frame-pointer)
  add_link_options(-fsanitize=${FLEETNAV_SANITIZE})
endif()
