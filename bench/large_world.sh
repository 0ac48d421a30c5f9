#!/usr/bin/env bash
# The graph SLAM in a large simulated world: simulates bench/worlds/WORLD.yaml
# (campus_loop: a 140 m x 60 m ring of self-similar corridors, once round and 40 m on;
# hospital_floor: two wings of wards, ten people walking) with the laser of a long-range log (a
# SICK at 1 deg, 80 m, interlacing four start angles a quarter degree apart), seeds 1..N, at the
# default odometry noise and at four times it; runs `splam slam --method graph` on each log and
# prints the position RMSE of the estimate and of the odometry, the loop closures and the
# self-consistency check's verdict.
# Usage: bench/large_world.sh WORLD [SEEDS] [BUILD_DIR] [OUT_DIR]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
world=${1:?usage: bench/large_world.sh campus_loop|hospital_floor [SEEDS] [BUILD_DIR] [OUT_DIR]}
seeds=${2:-10}
build=${3:-$here/../build}
out=${4:-runs/$world}
splam=$build/apps/splam
mkdir -p "$out"
printf '| odometry noise | seed | estimate RMSE (m) | odometry RMSE (m) | loop closures | scans inconsistent | flagged | wall time (s) |\n'
printf '|---|---|---|---|---|---|---|---|\n'
for noise in 1 4; do
  for seed in $(seq 1 "$seeds"); do
    run=$out/noise$noise-seed$seed
    "$splam" simulate --world "$here/worlds/$world.yaml" --laser lms200-1deg \
      --set simulator.laser.max_range_m=80 --set simulator.laser.interlace_phases=4 \
      --odometry-noise "$noise" --seed "$seed" --out "$run/sim" > "$run.simulate.txt"
    "$splam" slam --method graph --odometry-noise "$noise" "$run/sim/log.clf" --out "$run/graph" \
      > "$run.slam.txt" || true
    python3 - "$run/graph/summary.json" "$noise" "$seed" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
e, c = s["error"], s["consistency"]
print(f"| {sys.argv[2]}x | {sys.argv[3]} | {e['estimate']['rmse_position_m']:.3f} | "
      f"{e['odometry']['rmse_position_m']:.3f} | {s['associations']['loop_accepted']} | "
      f"{100 * c['inconsistent_share']:.1f} % | {'yes' if c['flagged'] else 'no'} | "
      f"{s['wall_time_s']:.1f} |")
PY
  done
done
