#!/usr/bin/env bash
# ThreadSanitizer over the code that runs on more than one thread: the registries
# (kernel::Registry) and the graph SLAM's background loop search
# (LoopClosureOptions::background_search). Configures build-tsan (Clang, SPLAM_TSAN), builds
# kernel_test and estimation_test and runs the tests that drive the threads, with any
# report failing the run. Run it before resolving a change to threaded code; it is not part of
# the test command (the instrumented build takes about ten minutes on two cores).
# Usage: bash scripts/tsan.sh [GTEST_FILTER]
set -euo pipefail
cd "$(dirname "$0")/.."
CC=clang CXX=clang++ cmake -S . -B build-tsan -G Ninja -DCMAKE_BUILD_TYPE=Release -DSPLAM_TSAN=ON \
  -DSPLAM_BUILD_TESTS=ON -DSPLAM_BUILD_EXAMPLES=OFF -DSPLAM_BUILD_BENCHMARKS=OFF > /dev/null
cmake --build build-tsan --parallel "$(nproc 2>/dev/null || echo 2)" --target estimation_test \
  kernel_test
export TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1
build-tsan/tests/kernel_test --gtest_brief=1 --gtest_filter='Registry.*'
build-tsan/tests/estimation_test --gtest_brief=1 \
  --gtest_filter="${1:-*Background*}"
