# Thin front door: every target first runs the idempotent setup, then CMake.
# CMake 4.3 lives in .tools/bin (installed by scripts/setup.sh).
export PATH := $(CURDIR)/.tools/bin:$(PATH)

.PHONY: all setup configure build test demo bench golden clean
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
	@build/bin/rocking plot response --out plots --name demo_response

# Reruns the paper's checks, rewrites tests/golden/paper_checks.tsv and prints
# the README's table: only after a change that moves the numbers on purpose.
golden: build
	@ROCKING_WRITE_GOLDEN=1 build/bin/golden_test -tc="the paper's checks*" -s 2>&1 | sed -n '/^| case/,/^$$/p'

# Machine, command and results: Google Benchmark prints the CPU and the load.
bench: build
	@echo "machine: $$(nproc) cores, $$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
	@echo "command: build/bin/integrators_bench --benchmark_counters_tabular=true"
	@build/bin/integrators_bench --benchmark_counters_tabular=true
	@echo "command: build/bin/run_bench"
	@build/bin/run_bench
	@echo "command: build/bin/study_bench"
	@build/bin/study_bench

clean:
	@rm -rf build
