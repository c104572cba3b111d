# phynjo — the two commands of the quick start (`make demo`, `make test`) and friends.
# Each target installs what is missing (scripts/install-deps), configures and builds as needed.
BUILD      ?= build
BUILD_TYPE ?= Release
JOBS       ?= $(shell nproc 2>/dev/null || echo 2)
CMAKE_ARGS ?=

.PHONY: all deps configure build test test-sanitize fuzz demo bench install clean

all: build

deps:
	@scripts/install-deps

$(BUILD)/CMakeCache.txt: | deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) $(CMAKE_ARGS)

configure: deps $(BUILD)/CMakeCache.txt

build: configure
	cmake --build $(BUILD) -j $(JOBS)

test: build
	ctest --test-dir $(BUILD) --output-on-failure -j $(JOBS)

# The whole test suite again under AddressSanitizer + UndefinedBehaviorSanitizer (GCC's);
# any report fails the run.
test-sanitize: deps
	cmake -S . -B $(BUILD)-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPHYNJO_SANITIZE=ON $(CMAKE_ARGS)
	cmake --build $(BUILD)-sanitize -j $(JOBS)
	ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1 \
	UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	ctest --test-dir $(BUILD)-sanitize --output-on-failure -j $(JOBS)

# libFuzzer (clang) on the expression parser, the .lag front end and the CAS passes, each for
# FUZZ_SECONDS; inputs the fuzzers keep are written to fuzz/corpus/ (commit them: the
# corpus replays as ordinary tests); crashes, timeouts and slow inputs to $(BUILD)-fuzz/artifacts/.
FUZZ_SECONDS ?= 600
fuzz: deps
	PHYNJO_FUZZ_DEPS=1 scripts/install-deps
	CC=clang CXX=clang++ cmake -S . -B $(BUILD)-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPHYNJO_SANITIZE=ON \
	  -DPHYNJO_FUZZ=ON -DPHYNJO_BUILD_TESTS=OFF $(CMAKE_ARGS)
	cmake --build $(BUILD)-fuzz -j $(JOBS) --target fuzz_expression fuzz_lag fuzz_cas
	mkdir -p $(BUILD)-fuzz/artifacts
	for t in expression lag cas; do \
	  $(BUILD)-fuzz/fuzz/fuzz_$$t -max_total_time=$(FUZZ_SECONDS) -timeout=10 -rss_limit_mb=2048 \
	    -max_len=4096 -print_final_stats=1 -artifact_prefix=$(BUILD)-fuzz/artifacts/ fuzz/corpus/$$t || exit 1; \
	done

demo: build
	@scripts/demo $(BUILD)

bench: deps
	PHYNJO_BENCH_DEPS=1 scripts/install-deps
	cmake -S . -B $(BUILD)-bench -DCMAKE_BUILD_TYPE=Release -DPHYNJO_BUILD_BENCH=ON -DPHYNJO_BUILD_TESTS=OFF -DPHYNJO_NATIVE=ON $(CMAKE_ARGS)
	cmake --build $(BUILD)-bench -j $(JOBS)
	@bench/run-all $(BUILD)-bench

install: build
	cmake --install $(BUILD) $(if $(PREFIX),--prefix $(PREFIX),)

clean:
	rm -rf $(BUILD) $(BUILD)-bench $(BUILD)-sanitize $(BUILD)-fuzz demo-output
