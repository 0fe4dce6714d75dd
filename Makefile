# The two set-up commands of the README, and a few shortcuts.
#   make run    install missing packages, build, run the demo (see README)
#   make test   install missing packages, build, run the whole suite, then again under ASan + UBSan
BUILD      ?= build
BUILD_SAN  ?= build-asan
MAKEFLAGS  += --no-print-directory
JOBS       ?= $(shell nproc 2>/dev/null || echo 2)
CMAKE_ARGS ?=

.PHONY: all deps build build-asan run test test-fast test-asan golden clean

all: build

deps:
	@bash scripts/deps.sh

build: deps
	@cmake -S . -B $(BUILD) -DSINEW_WERROR=ON $(CMAKE_ARGS) >/dev/null
	@cmake --build $(BUILD) -j $(JOBS)

build-asan: deps
	@cmake -S . -B $(BUILD_SAN) -DSINEW_WERROR=ON -DSINEW_SANITIZE=ON -DCMAKE_BUILD_TYPE=Debug $(CMAKE_ARGS) >/dev/null
	@cmake --build $(BUILD_SAN) -j $(JOBS)

run: build
	@bash scripts/run-demo.sh $(BUILD)

test-fast: build
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

test-asan: build-asan
	@cd $(BUILD_SAN) && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
		ctest --output-on-failure -j $(JOBS)

test: test-fast test-asan

# Re-render tests/golden/*.png after an intended change to the pictures; look at them before committing.
golden: build
	@cd $(BUILD) && SINEW_UPDATE_GOLDEN=1 ctest -R test_render --output-on-failure

clean:
	rm -rf $(BUILD) $(BUILD_SAN)
