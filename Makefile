# The two set-up commands of the README, and a few shortcuts.
#   make run    install missing packages, build, run the demo (see README)
#   make test   install missing packages, build, run the whole suite, then again under ASan + UBSan
BUILD      ?= build
BUILD_SAN  ?= build-asan
MAKEFLAGS  += --no-print-directory
JOBS       ?= $(shell nproc 2>/dev/null || echo 2)
CMAKE_ARGS ?=

.PHONY: all deps build build-asan run test test-fast test-asan golden fuzz clean

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

# libFuzzer (needs clang) on the .sinew reader (seeded from fuzz/corpus), the FBX, glTF and
# COLLADA readers (seeded from tests/fixtures), the muscle JSON reader, the import helper's
# reply and the player, FUZZ_SECONDS each (60 by default). New inputs go
# to build-fuzz/corpus-*; crashes to build-fuzz/crash-*.
FUZZ_SECONDS ?= 60
fuzz: deps
	@cmake -S . -B build-fuzz -DCMAKE_C_COMPILER=clang -DSINEW_FUZZ=ON -DSINEW_TESTS=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
	@cmake --build build-fuzz -j $(JOBS) --target fuzz_model fuzz_fbx fuzz_gltf fuzz_collada fuzz_iqm fuzz_bvh fuzz_muscles fuzz_reply fuzz_player
	@mkdir -p build-fuzz/corpus-muscles build-fuzz/seeds-muscles build-fuzz/corpus-reply build-fuzz/corpus-player build-fuzz/corpus-model build-fuzz/corpus-fbx build-fuzz/seeds-fbx build-fuzz/corpus-gltf build-fuzz/seeds-gltf build-fuzz/corpus-collada build-fuzz/seeds-collada build-fuzz/corpus-iqm build-fuzz/seeds-iqm build-fuzz/corpus-bvh build-fuzz/seeds-bvh
	@cp tests/fixtures/*.fbx build-fuzz/seeds-fbx/
	@cp tests/fixtures/*.gltf tests/fixtures/*.glb build-fuzz/seeds-gltf/
	@cp tests/fixtures/*.dae build-fuzz/seeds-collada/
	@cp tests/fixtures/*.iqm build-fuzz/seeds-iqm/
	@cp tests/fixtures/*.bvh build-fuzz/seeds-bvh/
	@cp tests/fixtures/*.json data/*.json build-fuzz/seeds-muscles/
	@cd build-fuzz && ./fuzz_model -max_total_time=$(FUZZ_SECONDS) -max_len=65536 corpus-model ../fuzz/corpus
	@cd build-fuzz && ./fuzz_fbx -max_total_time=$(FUZZ_SECONDS) -max_len=65536 -timeout=10 -rss_limit_mb=4096 corpus-fbx seeds-fbx
	@cd build-fuzz && ./fuzz_gltf -max_total_time=$(FUZZ_SECONDS) -max_len=65536 -timeout=10 -rss_limit_mb=4096 corpus-gltf seeds-gltf
	@cd build-fuzz && ./fuzz_collada -max_total_time=$(FUZZ_SECONDS) -max_len=65536 -timeout=10 -rss_limit_mb=4096 corpus-collada seeds-collada
	@cd build-fuzz && ./fuzz_iqm -max_total_time=$(FUZZ_SECONDS) -max_len=65536 -timeout=10 -rss_limit_mb=4096 corpus-iqm seeds-iqm
	@cd build-fuzz && ./fuzz_bvh -max_total_time=$(FUZZ_SECONDS) -max_len=65536 -timeout=10 -rss_limit_mb=4096 corpus-bvh seeds-bvh
	@cd build-fuzz && ./fuzz_muscles -max_total_time=$(FUZZ_SECONDS) -max_len=65536 -timeout=10 corpus-muscles seeds-muscles
	@cd build-fuzz && ./fuzz_reply -max_total_time=$(FUZZ_SECONDS) -max_len=65536 -timeout=10 corpus-reply ../fuzz/corpus
	@cd build-fuzz && ./fuzz_player -max_total_time=$(FUZZ_SECONDS) -max_len=65536 -timeout=10 corpus-player ../fuzz/corpus

clean:
	rm -rf $(BUILD) $(BUILD_SAN) build-fuzz
