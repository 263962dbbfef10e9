# Every third-party dependency, found as TOOLCHAIN.md prescribes for Debian 12.
find_package(Threads REQUIRED)
find_package(PkgConfig REQUIRED)
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(absl CONFIG REQUIRED)
find_package(yaml-cpp REQUIRED)
find_package(Protobuf REQUIRED)
find_package(gRPC CONFIG REQUIRED)
find_package(SQLite3 REQUIRED)
find_package(PostgreSQL REQUIRED)  # libpq (libpq-dev): the PostgreSQL store
find_package(PNG REQUIRED)  # map images (libpng-dev)
find_package(OpenSSL REQUIRED)  # token hashes (libssl-dev); gRPC itself uses it for TLS
pkg_check_modules(ODE REQUIRED IMPORTED_TARGET ode)
pkg_check_modules(CAIRO REQUIRED IMPORTED_TARGET GLOBAL cairo)  # PNG and SVG pictures
find_package(spdlog REQUIRED)
find_package(prometheus-cpp CONFIG REQUIRED)  # fleetnavd's /metrics (prometheus-cpp-dev)
pkg_check_modules(HTTPLIB REQUIRED IMPORTED_TARGET GLOBAL cpp-httplib)  # fleetnavd's HTTP port
find_package(CLI11 CONFIG REQUIRED)
find_package(nlohmann_json 3 REQUIRED)

# OMPL exports variables only; its ompl.pc forces -std=c++14, so wrap the variables.
find_package(ompl REQUIRED)
add_library(fleetnav_ompl INTERFACE)
target_include_directories(fleetnav_ompl SYSTEM INTERFACE ${OMPL_INCLUDE_DIRS})
target_link_libraries(fleetnav_ompl INTERFACE ${OMPL_LIBRARIES})

if(FLEETNAV_BUILD_TESTS)
  find_package(GTest REQUIRED)
  find_package(benchmark REQUIRED)
endif()

# yaml-cpp 0.7 on Debian exports the plain target name.
if(TARGET yaml-cpp::yaml-cpp)
  set(FLEETNAV_YAML yaml-cpp::yaml-cpp)
else()
  set(FLEETNAV_YAML yaml-cpp)
endif()
