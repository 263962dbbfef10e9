# The two commands of the README: `make demo` and `make test`. Both bootstrap the machine
# (installing only missing Debian packages), configure, build, then run.
BUILD_DIR ?= build
JOBS ?= 2
BUILD_TYPE ?= RelWithDebInfo
FLEETNAV_WERROR ?= OFF

# Test programs built with ASan + UBSan by `make sanitize`: the pure libraries with the most
# index arithmetic.
SANITIZE_TESTS ?= core_test planner_test storage_test localization_test
# Test programs built with TSan by `make tsan`: the libraries whose classes are shared between
# threads (clocks, the SQLite store, the registry, the job services and the dispatcher thread),
# linked with an Abseil built with TSan (scripts/tsan-abseil; Debian's is not instrumented).
TSAN_TESTS ?= core_test storage_test server_app_test

.PHONY: all bootstrap configure build test demo bench format format-check tidy tidy-changed sanitize tsan fuzz clean

all: build

bootstrap:
	./scripts/bootstrap

configure: bootstrap
	cmake -S . -B $(BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) \
	  -DFLEETNAV_WERROR=$(FLEETNAV_WERROR) -DCMAKE_EXPORT_COMPILE_COMMANDS=ON

build: configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

# Every test runs once: the closed-loop scenario tests (label `scenario`) run in lockstep with
# fleetnavd and the agents, so a run is the same run under any load (docs/simulator.md) and a
# test that fails is a bug, not a flake. The scenarios run after the rest.
test: build
	ctest --test-dir $(BUILD_DIR) --output-on-failure -j $(JOBS) --timeout 600 -LE scenario
	ctest --test-dir $(BUILD_DIR) --output-on-failure -j $(JOBS) --timeout 900 -L scenario

demo: build
	./scripts/demo $(BUILD_DIR)

format:
	git ls-files '*.cpp' '*.hpp' | xargs clang-format -i

# Fails on any C++ file clang-format would change.
format-check:
	git ls-files '*.cpp' '*.hpp' | xargs clang-format --dry-run -Werror

# clang-tidy (.clang-tidy: naming rules and defect checks) on the whole tree, cached per
# preprocessed file (scripts/tidy-all; needs the build's generated headers).
tidy: build
	JOBS=$(JOBS) ./scripts/tidy-all $(BUILD_DIR)

# The same on the files changed in the last day only (quick, no cache).
tidy-changed: configure
	./scripts/tidy-changed $(BUILD_DIR)

sanitize: bootstrap
	JOBS=$(JOBS) ./scripts/sanitized-tests address,undefined build-asan $(SANITIZE_TESTS)

tsan: bootstrap
	absl_dir=$$(./scripts/tsan-abseil build-tsan/abseil) && \
	  CMAKE_ARGS="-Dabsl_DIR=$$absl_dir" JOBS=$(JOBS) \
	  ./scripts/sanitized-tests thread build-tsan/fleetnav $(TSAN_TESTS)

# Every fuzz target (fuzz/) with libFuzzer + ASan + UBSan for FUZZ_SECONDS each (default 60).
fuzz: bootstrap
	JOBS=$(JOBS) ./scripts/fuzz build-fuzz

clean:
	rm -rf $(BUILD_DIR) build-asan build-tsan
