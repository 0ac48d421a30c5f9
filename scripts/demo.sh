#!/usr/bin/env bash
# README command (a): install what is missing, build, and run the main job on its built-in
# default. Today the main job is `splam simulate` in the `complex` world; the run directory is
# runs/complex (a CARMEN log with ground truth, trajectories, world.yaml, run.svg, run.png).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh -DSPLAM_BUILD_TESTS=OFF -DSPLAM_BUILD_BENCHMARKS=OFF -DSPLAM_BUILD_EXAMPLES=OFF
build/apps/splam simulate --world complex --seed 1 --out runs/complex
build/apps/splam slam --method ekf-bspline --association curvature runs/complex/log.clf \
  --out runs/complex-bspline
echo "Open runs/complex/run.png (the run) and runs/complex-bspline/map.png (its B-spline map)."
