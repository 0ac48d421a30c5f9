#!/usr/bin/env bash
# The installed package as a user meets it: `cmake --install` the build into
# a fresh prefix, build examples/out_of_tree against it (find_package(splam), splam::cli), and
# run its program: two SLAM variants and an explorer variant registered in a line each, offered by
# splam's subcommands. Usage: out_of_tree_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1
source=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
test -x "$work/prefix/bin/splam"
test -f "$work/prefix/include/splam/apps/cli.h"
test -f "$work/prefix/lib/cmake/splam/splamConfig.cmake"
generator=()
command -v ninja > /dev/null && generator=(-G Ninja)
cmake -S "$source/examples/out_of_tree" -B "$work/build" "${generator[@]}" \
  -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_BUILD_TYPE=Release > "$work/configure.log"
cmake --build "$work/build" --parallel 2 > "$work/build.log"
program=$work/build/my_splam
"$program" --help > "$work/help.txt"
"$program" slam --help > "$work/slam-help.txt"
grep -q "dead-reckoning: the odometry alone" "$work/slam-help.txt"
"$program" explore --help > "$work/explore-help.txt"
grep -q "nearest: REG taking first the frontier nearest" "$work/explore-help.txt"
"$program" simulate --world corridor --route built-in --out "$work/sim" > /dev/null
"$program" slam --method dead-reckoning "$work/sim/log.clf" --out "$work/slam" > /dev/null
test -s "$work/slam/trajectory.txt"
grep -q '"scans"' "$work/slam/summary.json"
"$program" slam --method graph-unconfirmed "$work/sim/log.clf" --out "$work/graph" > /dev/null
grep -q '"method": "graph-unconfirmed"' "$work/graph/summary.json"
grep -q '"loop_accepted"' "$work/graph/summary.json"
"$program" explore --explorer nearest --localization ground-truth --world corridor \
  --out "$work/explore" > /dev/null
grep -q '"nearest"' "$work/explore/report.json"
# The installed splam program is the same command line.
"$work/prefix/bin/splam" config print --method graph > "$work/config.yaml"
grep -q merge_trimmed_keyframes "$work/config.yaml"
echo "out-of-tree project built against the installed package and ran both variants"
