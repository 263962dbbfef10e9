# fleetnav_module(NAME <target> SOURCES ... DEPS ...): one static library per module, public
# headers in include/, warnings on.
function(fleetnav_module)
  cmake_parse_arguments(ARG "" "NAME" "SOURCES;DEPS" ${ARGN})
  add_library(${ARG_NAME} STATIC ${ARG_SOURCES})
  target_include_directories(${ARG_NAME} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
  target_link_libraries(${ARG_NAME} PUBLIC ${ARG_DEPS} PRIVATE fleetnav_warnings)
endfunction()

# Tests write their scratch files here (TMPDIR), not in the machine's /tmp; the test_tmp
# fixture (tests/CMakeLists.txt) empties it at the start of each ctest run.
set(FLEETNAV_TEST_TMPDIR ${CMAKE_BINARY_DIR}/test-tmp)

# fleetnav_test(NAME <name> SOURCES ... DEPS ... [LABELS ...]): one GoogleTest binary.
function(fleetnav_test)
  cmake_parse_arguments(ARG "" "NAME" "SOURCES;DEPS;LABELS" ${ARGN})
  add_executable(${ARG_NAME} ${ARG_SOURCES})
  target_link_libraries(${ARG_NAME} PRIVATE ${ARG_DEPS} GTest::gtest_main GTest::gmock fleetnav_warnings)
  include(GoogleTest)
  # Test names start with their program ("server_app_test.FleetRegistryTest.X"), so that
  # `ctest -R` can pick the tests of one program or module.
  gtest_discover_tests(${ARG_NAME} DISCOVERY_TIMEOUT 60 TEST_PREFIX "${ARG_NAME}."
    PROPERTIES LABELS "${ARG_LABELS}" ENVIRONMENT "TMPDIR=${FLEETNAV_TEST_TMPDIR}"
    FIXTURES_REQUIRED test_tmp)
endfunction()

# fleetnav_benchmark(NAME <name> SOURCES ... DEPS ...): one Google Benchmark program.
function(fleetnav_benchmark)
  cmake_parse_arguments(ARG "" "NAME" "SOURCES;DEPS" ${ARGN})
  add_executable(${ARG_NAME} ${ARG_SOURCES})
  target_link_libraries(${ARG_NAME} PRIVATE ${ARG_DEPS} benchmark::benchmark fleetnav_warnings)
endfunction()
