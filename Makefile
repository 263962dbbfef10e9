# The two commands of the README: `make demo` and `make test`. Both bootstrap the machine
# (installing only missing Debian packages), configure, build, then run.
BUILD_DIR ?= build
JOBS ?= 2
BUILD_TYPE ?= RelWithDebInfo
FLEETNAV_WERROR ?= OFF

.PHONY: all bootstrap configure build test demo bench format clean

all: build

bootstrap:
	./scripts/bootstrap

configure: bootstrap
	cmake -S . -B $(BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) \
	  -DFLEETNAV_WERROR=$(FLEETNAV_WERROR) -DCMAKE_EXPORT_COMPILE_COMMANDS=ON

build: configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

# Closed-loop scenario tests (label `scenario`) run in wall-clock time beside each other, so a
# run can go differently under load: each may run twice, and fails `make test` only when it
# fails both times. Every other test runs once.
test: build
	ctest --test-dir $(BUILD_DIR) --output-on-failure -j $(JOBS) --timeout 600 -LE scenario
	ctest --test-dir $(BUILD_DIR) --output-on-failure -j $(JOBS) --timeout 600 -L scenario \
	  --repeat until-pass:2

demo: build
	./scripts/demo $(BUILD_DIR)

format:
	git ls-files '*.cpp' '*.hpp' | xargs clang-format -i

clean:
	rm -rf $(BUILD_DIR)
