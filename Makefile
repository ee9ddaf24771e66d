# Makefile - set up, build, run, test and benchmark authalic (a thin wrapper over CMake).
# The program lands at $(BUILD_DIR)/authalic. Variables may be overridden: make run DEFAULT_MESH=my.obj
#
#   make test   the whole ctest suite twice: the normal build ($(BUILD_DIR)), then a build with
#               AddressSanitizer + UndefinedBehaviorSanitizer ($(ASAN_DIR)), where a leak
#               (LeakSanitizer), an invalid access or undefined behaviour makes the test fail
#   make fuzz   the libFuzzer targets of tests/fuzz built with clang ($(FUZZ_DIR)), each run for
#               FUZZ_SECONDS; any finding fails (tests/fuzz/run.sh says where it was saved)
#   make bench  bench/bench.sh --results bench/RESULTS.md: the shared meshes' sphere, planar and thin-limb
#               tables, with the date, the CPU and the load average in the page's header
#   make scale  bench/scale.sh: generated meshes of 10k..1M faces mapped under /usr/bin/time -v
#   make python the Python package (python/) installed for $(PYTHON) with its copy of the library;
#               its pytest suite runs in `make test` (ctest cases python.test_*, one per file, both builds)

BUILD_DIR ?= build
ASAN_DIR ?= build-asan
FUZZ_DIR ?= build-fuzz
BUILD_TYPE ?= Release
JOBS ?= 2
FUZZ_SECONDS ?= 60
DEFAULT_MESH ?= data/bumpy_star.obj
PYTHON ?= /usr/bin/python3

# Sanitizer findings exit with 86, a status no test expects (the CLI's own are 0, 1 and 2), so a
# leak in a run that was meant to fail still fails its test.
SAN_ENV = ASAN_OPTIONS=detect_leaks=1:exitcode=86:check_initialization_order=1:strict_string_checks=1 \
          UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1:exitcode=86 LSAN_OPTIONS=exitcode=86

.PHONY: all setup build build-asan build-fuzz run test test-asan fuzz bench scale python clean

all: build

setup:
	bash scripts/setup-debian.sh

build: setup
	cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=$(BUILD_TYPE)
	cmake --build $(BUILD_DIR) -j$(JOBS)

# -O1 -g with assertions on (no NDEBUG): the configuration sanitizers are meant for.
build-asan: setup
	cmake -S . -B $(ASAN_DIR) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g" \
	  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" -DAU_SANITIZE=ON
	cmake --build $(ASAN_DIR) -j$(JOBS)

run: build
	mkdir -p $(BUILD_DIR)/out
	./$(BUILD_DIR)/authalic sphere $(DEFAULT_MESH) $(BUILD_DIR)/out/default_sphere.obj \
	  --report $(BUILD_DIR)/out/default_sphere.json

# Both suites run even when the first fails, so one CI run shows every failure.
test: build build-asan
	@rc=0; \
	echo "== ctest: $(BUILD_DIR)"; \
	ctest --test-dir $(BUILD_DIR) --output-on-failure -j$(JOBS) || rc=1; \
	echo "== ctest under AddressSanitizer + UndefinedBehaviorSanitizer + LeakSanitizer: $(ASAN_DIR)"; \
	$(SAN_ENV) ctest --test-dir $(ASAN_DIR) --output-on-failure -j$(JOBS) || rc=1; \
	exit $$rc

test-asan: build-asan
	$(SAN_ENV) ctest --test-dir $(ASAN_DIR) --output-on-failure -j$(JOBS)

build-fuzz: setup
	cmake -S tests/fuzz -B $(FUZZ_DIR) -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++
	cmake --build $(FUZZ_DIR) -j$(JOBS) --target fuzz_read_obj fuzz_read_off fuzz_read_ply fuzz_read_stl \
	  fuzz_read_freesurfer fuzz_read_gifti fuzz_cli

fuzz: build-fuzz
	bash tests/fuzz/run.sh $(FUZZ_DIR) $(FUZZ_SECONDS)

bench: build
	bash bench/bench.sh --results bench/RESULTS.md

scale: build
	bash bench/scale.sh --build $(BUILD_DIR)

# Debian's interpreter (python3-numpy), not a python3 found first on PATH.
python: build
	sh python/install.sh $(PYTHON) $(BUILD_DIR)

clean:
	rm -rf $(BUILD_DIR) $(ASAN_DIR) $(FUZZ_DIR)
