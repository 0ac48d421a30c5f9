#!/usr/bin/env bash
# Configures build-san: Clang with AddressSanitizer, UndefinedBehaviorSanitizer and libFuzzer's
# coverage (SPLAM_FUZZ), tests on, examples and benchmarks off. scripts/fuzz.sh and
# scripts/sanitize.sh build their targets there.
set -euo pipefail
cd "$(dirname "$0")/.."
CC=clang CXX=clang++ cmake -S . -B build-san -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DSPLAM_FUZZ=ON -DSPLAM_BUILD_TESTS=ON -DSPLAM_BUILD_EXAMPLES=OFF \
  -DSPLAM_BUILD_BENCHMARKS=OFF > /dev/null
