# Thin front door: every target first runs the idempotent setup, then CMake.
# CMake 4.3 lives in .tools/bin (installed by scripts/setup.sh).
export PATH := $(CURDIR)/.tools/bin:$(PATH)

.PHONY: all setup setup-program configure configure-program build program test demo bench golden sanitize fuzz pgo extension-check clean
all: build

setup:
	@bash scripts/setup.sh

# What the program alone needs (scripts/setup.sh says which packages): most of
# the download (Chromium, ffmpeg, Matplotlib) is the tests' and examples'.
setup-program:
	@bash scripts/setup.sh program

configure: setup
	@cmake --preset default >/dev/null

configure-program: setup-program
	@cmake --preset default >/dev/null

build: configure
	@cmake --build --preset default

test: build
	@ctest --preset default

# The program and the plugins it loads, not the tests, fuzzers or benchmarks,
# with only the packages they need installed.
program: configure-program
	@cmake --build --preset default --target rocking_cli

demo: program
	@build/bin/rocking plot response --out plots --name demo_response

# The whole suite under AddressSanitizer + UndefinedBehaviorSanitizer, in its
# own build folder (build-sanitize); the allocation test, which replaces the
# allocator, is not built there, and the seven tests that run whole studies
# skip themselves (tests/sanitizers.hpp: `make test` runs them). The mpirun test's ranks run without leak
# detection (OpenMPI's own leaks come unnamed; tests/study_cli_test.cpp says why).
sanitize: setup
	@cmake --preset sanitize >/dev/null
	@cmake --build --preset sanitize
	@ctest --preset sanitize

# Each fuzz target (tests/fuzz) for FUZZ_SECONDS under the sanitizers, from
# the committed corpus and the shared records and scenes as seeds; new inputs
# that reach new code go to build-sanitize/fuzz-corpus. A crash stops with the
# input saved as build-sanitize/crash-*: fix it, and commit the input under
# tests/fuzz/regressions/TARGET, which make test replays. FUZZ_TARGETS="scene
# set_override" (names as in scripts/fuzz.sh) runs only those.
FUZZ_SECONDS ?= 60
fuzz: setup
	@cmake --preset sanitize >/dev/null
	@cmake --build --preset sanitize --target record_fuzz scene_fuzz set_override_fuzz number_list_fuzz cyclic_test_fuzz device_set_fuzz option_value_fuzz processing_fuzz lab_request_fuzz history_csv_fuzz study_csv_fuzz
	@bash scripts/fuzz.sh $(FUZZ_SECONDS)

# A new history quantity in 2 files reaches history.csv, the response figure
# and the lab: tests/extension/new_quantity.patch applied to a scratch copy of
# the committed tree (under build/, removed after), the program built there
# (the quick preset) and run (scripts/extension_check.sh). Not in make test
# (it builds the program once more): CI runs it after make test (.ci/run).
extension-check: setup
	@bash scripts/extension_check.sh

# Reruns the paper's checks and the README's suite study, rewrites
# tests/golden/paper_checks.tsv and tests/golden/suite_fragility.csv, and prints
# the README's table: only after a change that moves the numbers on purpose.
golden: build
	@ROCKING_WRITE_GOLDEN=1 build/bin/unit_tests -tc="the paper's checks*" -s 2>&1 | sed -n '/^| case/,/^$$/p'
	@ROCKING_WRITE_GOLDEN=1 build/bin/unit_tests -tc="the README's suite study*" >/dev/null 2>&1 || true
	@echo "rewrote tests/golden/suite_fragility.csv:"; cat tests/golden/suite_fragility.csv

# Records a new profile for the release build's profile-guided optimisation
# (an instrumented build in build-pgo/, the training runs of scripts/pgo.sh)
# and writes data/pgo/rocking.proftext; the next build uses it.
pgo: setup
	@bash scripts/pgo.sh

# Machine, command and results: Google Benchmark prints the CPU and the load.
bench: build
	@cmake --build --preset default --target benchmarks
	@echo "machine: $$(nproc) cores, $$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
	@echo "command: build/bin/integrators_bench --benchmark_counters_tabular=true"
	@build/bin/integrators_bench --benchmark_counters_tabular=true
	@echo "command: build/bin/run_bench"
	@build/bin/run_bench
	@echo "command: build/bin/command_bench"
	@build/bin/command_bench
	@echo "command: build/bin/study_bench"
	@build/bin/study_bench
	@echo "command: build/bin/records_bench"
	@build/bin/records_bench
	@echo "command: build/bin/suite_bench"
	@build/bin/suite_bench
	@echo "command: build/bin/structures_bench"
	@build/bin/structures_bench
	@echo "command: build/bin/tower_bench --integrators auto --peaks"
	@build/bin/tower_bench --integrators auto --peaks
	@echo "command: build/bin/tower_bench --integrators rk45 --n 8,16,32 --budget 60"
	@build/bin/tower_bench --integrators rk45 --n 8,16,32 --budget 60
	@echo "command: PYTHONPATH=build/python /usr/bin/python3 bench/python_bench.py"
	@PYTHONPATH=build/python /usr/bin/python3 bench/python_bench.py
	@echo "command: build/bin/lab_bench"
	@build/bin/lab_bench
	@echo "command: ROCKING_BIN=build/bin/rocking ROCKING_LAB_MOVES=40 node lab/tests/browser.test.mjs"
	@ROCKING_BIN=build/bin/rocking ROCKING_LAB_MOVES=40 node lab/tests/browser.test.mjs
	@echo "command: ROCKING_BIN=build/bin/rocking node lab/tests/redraw.bench.mjs"
	@ROCKING_BIN=build/bin/rocking node lab/tests/redraw.bench.mjs

clean:
	@rm -rf build build-sanitize build-pgo build-quick
