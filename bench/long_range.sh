#!/usr/bin/env bash
# Worst-case step and memory of every SLAM method on a long-range laser:
# simulates bench/worlds/long_corridors.yaml (once round and 28 m on, 215 m) with a 181-beam SICK
# at 1 deg and an 80 m range, then runs each method over the log and prints its median and slowest step
# and its peak memory. Usage: bench/long_range.sh [BUILD_DIR] [OUT_DIR]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-$here/../build}
out=${2:-runs/long_range}
splam=$build/apps/splam
mkdir -p "$out"
"$splam" simulate --world "$here/worlds/long_corridors.yaml" --laser lms200-1deg \
  --set simulator.laser.max_range_m=80 --out "$out/sim" > "$out/simulate.txt"
tail -n 2 "$out/simulate.txt" | head -n 1
printf '| method | scans | wall time (s) | median step (ms) | slowest step (ms) | peak memory (MB) |\n'
printf '|---|---|---|---|---|---|\n'
for method in ekf-lines ekf-bspline topological graph; do
  "$splam" slam --method "$method" "$out/sim/log.clf" --out "$out/$method" > "$out/$method.txt"
  python3 - "$out/$method/summary.json" "$method" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
t = s["time_per_scan_ms"]
print(f"| {sys.argv[2]} | {s['scans']} | {s['wall_time_s']:.1f} | {t['median']:.2f} | {t['max']:.1f} | "
      f"{s['peak_memory_mb']:.0f} |")
PY
done
