# Makefile - set up, build, run, test and benchmark authalic (a thin wrapper over CMake).
# The program lands at $(BUILD_DIR)/authalic. Variables may be overridden: make run DEFAULT_MESH=my.obj

BUILD_DIR ?= build
BUILD_TYPE ?= Release
JOBS ?= 2
DEFAULT_MESH ?= data/bumpy_star.obj

.PHONY: all setup build run test bench clean

all: build

setup:
	bash scripts/setup-debian.sh

build: setup
	cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=$(BUILD_TYPE)
	cmake --build $(BUILD_DIR) -j$(JOBS)

run: build
	mkdir -p $(BUILD_DIR)/out
	./$(BUILD_DIR)/authalic sphere $(DEFAULT_MESH) $(BUILD_DIR)/out/default_sphere.obj \
	  --report $(BUILD_DIR)/out/default_sphere.json

test: build
	ctest --test-dir $(BUILD_DIR) --output-on-failure -j$(JOBS)

bench: build
	bash bench/bench.sh

clean:
	rm -rf $(BUILD_DIR)
