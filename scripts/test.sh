#!/usr/bin/env bash
# README command (b): install what is missing, build everything (library, app, examples,
# benchmarks, tests) with warnings as errors, run all tests, then the sanitizer stage. Tests that need the real logs
# skip with a message unless ../shared/datasets or $SPLAM_DATA holds them.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh -DSPLAM_WERROR=ON -DSPLAM_BUILD_TESTS=ON -DSPLAM_BUILD_EXAMPLES=ON -DSPLAM_BUILD_BENCHMARKS=ON
(cd build && ctest --output-on-failure --parallel "$(nproc 2>/dev/null || echo 2)")
# The sanitizer stage: the readers' and geometry's suites under ASan + UBSan, and every fuzz
# harness for 10 s (scripts/sanitize.sh says which suites and why).
bash scripts/sanitize.sh 10
