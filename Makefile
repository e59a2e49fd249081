# Thin front door: every target first runs the idempotent setup, then CMake.
# CMake 4.3 lives in .tools/bin (installed by scripts/setup.sh).
export PATH := $(CURDIR)/.tools/bin:$(PATH)

.PHONY: all setup configure build test demo clean
all: build

setup:
	@bash scripts/setup.sh

configure: setup
	@cmake --preset default >/dev/null

build: configure
	@cmake --build --preset default

test: build
	@ctest --preset default

demo: build
	@build/bin/rocking modal

clean:
	@rm -rf build
