#!/usr/bin/env bash
# Fuzzes every reader and the scan pipeline: builds the libFuzzer harnesses of tests/fuzz with
# Clang, ASan and UBSan in build-san (scripts/sanitize.sh shares it), then runs each for SECONDS
# (default 60) on its seed corpus (tests/fuzz/corpus/<name>, read only; new inputs go to
# build-san/runs/<name>/corpus). Prints the executions each survived; exits non-zero on a crash,
# a hang (10 s on one input), a leak or 4 GB of memory, leaving the input in
# build-san/runs/<name>/. The mutations start from FUZZ_SEED (default 1), so that a run repeats
# what an earlier one with the same seed tried first; FUZZ_SEED=0 draws a new seed each time.
# FUZZ_RUNS=N stops each harness after N executions if SECONDS have not passed first.
# Usage: [FUZZ_SEED=N] [FUZZ_RUNS=N] bash scripts/fuzz.sh [SECONDS] [NAME...]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
shift || true
bash scripts/setup.sh
bash scripts/configure_sanitized.sh
cmake --build build-san --target fuzzers --parallel "$(nproc 2>/dev/null || echo 2)"
names=("$@")
if ((${#names[@]} == 0)); then
  names=(carmen text_files world options floor_plan bag ros2_bag scan_features slam_step option_values
    sweep_state)
fi
export LSAN_OPTIONS=suppressions=$PWD/tests/lsan.supp
seed=${FUZZ_SEED:-1}
runs=${FUZZ_RUNS:--1}
status=0
printf '%-14s %12s %8s  %s\n' harness executions seconds result
for name in "${names[@]}"; do
  run=build-san/runs/$name
  mkdir -p "$run/corpus"
  log=$run/fuzz.log
  start=$SECONDS
  if build-san/tests/fuzz/fuzz_"$name" -seed="$seed" -runs="$runs" -max_total_time="$seconds" -timeout=10 \
      -rss_limit_mb=4096 -print_final_stats=1 -artifact_prefix="$run/" \
      "$run/corpus" "tests/fuzz/corpus/$name" > "$log" 2>&1; then
    result=ok
  else
    result="FAILED: see $log and the crash-/timeout-/leak- file in $run/"
    status=1
  fi
  executions=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$log" | grep -o '[0-9]*$' || echo 0)
  printf '%-14s %12s %8s  %s\n' "$name" "$executions" "$((SECONDS - start))" "$result"
done
exit $status
