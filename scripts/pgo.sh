#!/usr/bin/env bash
# Regenerates data/pgo/rocking.proftext, the profile that release builds are
# optimised with (CMakeLists.txt, ROCKING_PGO): builds the program with
# clang's instrumentation (the "pgo-generate" preset, build-pgo/), runs the
# training work below, and merges the counts into the text profile. Run it
# (`make pgo`) after changing code on the hot path: a function changed since
# the profile was taken is compiled without its counts, and the build warns
# that the profile is out of date.
#
# The training work is what users run most, each with the code paths it
# exercises: the chimney under a record with its history (rk45 and the exact
# full-contact steps, the damper, the history writer), a suite IDA scaled to
# PGA and one to Sa(T1) (the study path, spectra), a hunt, the rigid block,
# the controlled-rocking wall (its tendons), two towers (rk45, rosw), the
# structures with joints (the chain: stacked blocks, the segmental pier, the
# cracked chimney below its separation, rk45 and rosw) and on rocking columns
# (the frame, the chimney on columns), the record measures and the modal
# analysis. Code no training run reaches is compiled as cold (for size), so
# every shipped kind of structure is here. Single-threaded, so that a second
# recording differs from the first only where the clock steers the code (the
# thread pool's waits, the stop-signal polls) and in the few counts that
# follow from those.
# Usage: scripts/pgo.sh   ($ROCKING_RECORDS, else ../shared/data/records)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$here"
export PATH="$here/.tools/bin:$PATH"  # CMake 4.3 (scripts/setup.sh), as the Makefile does
records="${ROCKING_RECORDS:-$here/../shared/data/records}"
[ -f "$records/elcentro_1940_ns.at2" ] || { echo "pgo: no records in $records (set ROCKING_RECORDS)" >&2; exit 1; }
profdata="$(command -v llvm-profdata-19)" || { echo "pgo: llvm-profdata-19 not found (scripts/setup.sh installs llvm-19)" >&2; exit 1; }

cmake --preset pgo-generate >/dev/null
cmake --build --preset pgo-generate --target rocking_cli

raw="$here/build-pgo/profiles"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
rm -rf "$raw"
mkdir -p "$raw"
export LLVM_PROFILE_FILE="$raw/%p.profraw"
bin="$here/build-pgo/bin/rocking"
elcentro="$records/elcentro_1940_ns.at2"
few=("$records/elcentro_1940_ns.at2" "$records/christchurch2011_pphs_s57e.at2" "$records/kobe1995_kjma_000.at2")

echo "pgo: training"
for _ in 1 2 3; do "$bin" -q simulate --record "$elcentro" --out "$work/simulate" >/dev/null; done
"$bin" -q simulate --record "$elcentro" --scale 2 --out "$work/scaled" >/dev/null
"$bin" -q ida --suite horizontal --im pga --levels 0.2:3:0.2 --variants damper,no-damper --no-plot --threads 1 \
  --out "$work/suite" >/dev/null
"$bin" -q ida --record "${few[@]}" --im sa:T1 --levels 0.5:5:0.5 --variants damper,no-damper --no-plot --threads 1 \
  --out "$work/sa" >/dev/null
"$bin" -q ida --record "$elcentro" --variants damper,no-damper --hunt --no-plot --threads 1 --out "$work/hunt" >/dev/null
for scene in rigid_block controlled_rocking_wall towers/tower_8; do
  "$bin" -q simulate "data/scenes/$scene.toml" --record "$elcentro" --out "$work/scene" >/dev/null
done
"$bin" -q simulate data/scenes/towers/tower_32.toml --integrator rosw --record "$elcentro" --out "$work/rosw" >/dev/null
for scene in stacked_blocks segmental_pier rocking_frame chimney_on_columns; do
  for _ in 1 2; do "$bin" -q simulate "data/scenes/$scene.toml" --record "$elcentro" --out "$work/scene" >/dev/null; done
done
for _ in 1 2; do "$bin" -q simulate data/scenes/chimney_cracked.toml --record "$elcentro" --scale 0.2 --out "$work/scene" >/dev/null; done
"$bin" -q simulate data/scenes/stacked_blocks.toml --integrator rosw --record "$elcentro" --out "$work/rosw" >/dev/null
"$bin" -q simulate data/scenes/chimney_on_columns.toml --integrator rosw --record "$elcentro" --out "$work/rosw" >/dev/null
"$bin" -q record "${few[@]}" >/dev/null
"$bin" -q modal >/dev/null

# Every program has a main() of its own: the profile keeps none (the
# program's is a dispatch), so that the benchmarks and tools built with it are
# not told that theirs is out of date. Records are separated by blank lines.
"$profdata" merge --text -o "$work/profile.txt" "$raw"/*.profraw
awk 'BEGIN { RS = ""; ORS = "\n\n" } $1 != "main"' "$work/profile.txt" > "$here/data/pgo/rocking.proftext"
echo "pgo: wrote data/pgo/rocking.proftext ($(wc -c < "$here/data/pgo/rocking.proftext") bytes); rebuild with make build"
