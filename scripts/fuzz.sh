#!/usr/bin/env bash
# Runs every fuzz target of the sanitizer build for $1 seconds (default 60),
# from the committed corpus (tests/fuzz/corpus/TARGET) and seeds (the shared
# records, the project's scenes); stops at the first crash, leak or timeout.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
seconds="${1:-60}"
bin="$here/build-sanitize/bin"
records="${ROCKING_RECORDS:-$here/../shared/data/records}"
export ASAN_OPTIONS="detect_leaks=1:halt_on_error=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
declare -A seeds=(
  [record]="$records $records/formats"
  [scene]="$here/data/scenes"
  [set_override]=""
  [number_list]=""
  [cyclic_test]="$here/data/tests"
  [device_set]=""
  [option_value]=""
  [processing]=""
  [lab_request]=""
  [history_csv]=""
  [study_csv]=""
)
for target in ${FUZZ_TARGETS:-record scene set_override number_list cyclic_test device_set option_value processing lab_request history_csv study_csv}; do
  work="$here/build-sanitize/fuzz-corpus/$target"
  mkdir -p "$work"
  dirs=("$work")
  # A target with no regression yet has no folder for them (git keeps no empty folder).
  for s in "$here/tests/fuzz/corpus/$target" "$here/tests/fuzz/regressions/$target" ${seeds[$target]}; do
    if [ -d "$s" ]; then dirs+=("$s"); fi
  done
  echo "fuzz: $target for ${seconds} s"
  log="$here/build-sanitize/fuzz-$target.log"
  if ! (cd "$here/build-sanitize" && "$bin/${target}_fuzz" -max_total_time="$seconds" -timeout=10 \
        -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 "${dirs[@]}" >"$log" 2>&1); then
    # The report's first lines name the failing frame; its last ones the input.
    grep -m1 -A16 -E "ERROR|runtime error" "$log" || true
    echo "..."
    tail -n 14 "$log"
    echo "fuzz: $target failed (the input is build-sanitize/crash-* or leak-* or timeout-*; the whole log $log)" >&2
    exit 1
  fi
  tail -n 8 "$log"
done
echo "fuzz: every target ran ${seconds} s with no crash, leak or timeout"
