#!/usr/bin/env bash
# The sanitizer stage of the test command: in build-san (Clang, ASan + UBSan, see
# configure_sanitized.sh) it builds and runs the test suites of the readers and the geometry
# (io_test, sim_test, kernel_test, graph_test: every reader, the worlds, the CLI-free geometry
# and its property tests), then every fuzz harness for SECONDS (default 10) on its seed corpus.
# The other suites (estimation, exploration, loop, the CLI) run only in the normal build: under
# ASan they would double the test command's time. SANITIZE_ALL=1 runs them too (with a GoogleTest
# filter from SANITIZE_FILTER, default all): the command to run before resolving an issue.
# Any sanitizer report fails the stage.
# Usage: [SANITIZE_ALL=1] [SANITIZE_FILTER=PATTERN] bash scripts/sanitize.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-10}
jobs=$(nproc 2>/dev/null || echo 2)
bash scripts/configure_sanitized.sh
suites=(io_test sim_test kernel_test graph_test)
extra=()
if [[ ${SANITIZE_ALL:-0} == 1 ]]; then
  extra=(estimation_test exploration_test runtime_test apps_test)
fi
cmake --build build-san --parallel "$jobs" --target fuzzers splam "${suites[@]}" "${extra[@]}"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export LSAN_OPTIONS=suppressions=$PWD/tests/lsan.supp
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
for suite in "${suites[@]}"; do
  echo "sanitize: $suite"
  build-san/tests/"$suite" --gtest_brief=1
done
for suite in "${extra[@]}"; do
  echo "sanitize: $suite (${SANITIZE_FILTER:-*})"
  build-san/tests/"$suite" --gtest_brief=1 --gtest_filter="${SANITIZE_FILTER:-*}"
done
bash scripts/fuzz.sh "$seconds"
