#!/usr/bin/env bash
# Relocalization latency: each simulated sequence tracked for DURATION s, kidnapped (1 m / 10 deg, as if the track had
# silently gone wrong) at each of KIDNAP_TIMES, and once not kidnapped; then a table per run (losses, unverified
# stretch, fix found in replay time, the live estimate of scripts/kidnap_live_latency.py, error of the last frame).
#   bash scripts/kidnap_latency.sh [duration_s=30] [output_root=out/kidnap] [--set Section.key=value ...]
# KIDNAP_TIMES (environment, default "10 20"); SEQUENCES (default: the six). Simulations are reused when present.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BIN="${QUASILOC_BUILD_DIR:-$ROOT/build}/bin"
DURATION="${1:-30}"
OUT="${2:-out/kidnap}"
shift 2 || shift $#
read -r -a TIMES <<< "${KIDNAP_TIMES:-10 20}"
read -r -a SEQS <<< "${SEQUENCES:-V1_01_easy V1_02_medium V1_03_difficult V2_01_easy V2_02_medium V2_03_difficult}"
cd "$ROOT"
mkdir -p "$OUT"
for seq in "${SEQS[@]}"; do
  sim="$OUT/$seq/sim"
  if [ ! -s "$sim/gt.tum" ]; then
    "$BIN/sim-rawlog" "share/quasiloc/sim/$seq.ini" --set Simulation.output_dir="$sim" \
      --set Simulation.duration_s="$DURATION" --set Simulation.inspection_png=false > "$OUT/$seq.sim.log"
  fi
  for k in -1 "${TIMES[@]}"; do
    run="$OUT/$seq/k$k"
    "$BIN/quasiloc-track" config.ini --set Tracking.input_rawlog="$(ls "$sim"/*.rawlog | head -1)" \
      --set Tracking.calibration_ini="$sim/calib.ini" --set Tracking.map_file="$sim/lidar_map.map" \
      --set Tracking.groundtruth="$sim/gt.tum" --set Tracking.output_dir="$run" --set Tracking.write_scene=false \
      --set Tracking.kidnap_at_s="$k" "$@" > "$run.log"
  done
done
/usr/bin/python3 "$ROOT/scripts/kidnap_live_latency.py" "$OUT" | tee "$OUT.md"
