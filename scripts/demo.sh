#!/usr/bin/env bash
# README command (a): install what is missing, build, and run the main job on its built-in
# default. Today the main job is `splam simulate` in the `complex` world; the run directory is
# runs/complex (a CARMEN log with ground truth, trajectories, world.yaml, run.svg, run.png).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh -DSPLAM_BUILD_TESTS=OFF -DSPLAM_BUILD_BENCHMARKS=OFF -DSPLAM_BUILD_EXAMPLES=OFF
# The main job: REG exploration with topological B-spline SLAM in the built-in `complex` world.
build/apps/splam explore --out runs/explore
echo "Open runs/explore/map.png (map over the true world), runs/explore/graph.png (exploration"
echo "graph) and runs/explore/errors.png (x, y, theta error); numbers in runs/explore/report.json."
