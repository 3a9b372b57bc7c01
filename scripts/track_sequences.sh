#!/usr/bin/env bash
# Tracks the six simulated EuRoC trajectories (share/quasiloc/sim/<SEQ>.ini) with the top-level config.ini's
# tracker settings and prints one error/time row per sequence (quasiloc-track's own summary lines).
#   bash scripts/track_sequences.sh [duration_s=30, 0 = the whole sequence] [output_root=out/sequences] [sequences...]
# Simulated folders are reused when present (delete them to simulate again). Needs a built tree (scripts/build.sh).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BIN="${QUASILOC_BUILD_DIR:-$ROOT/build}/bin"
DURATION="${1:-30}"
OUT="${2:-out/sequences}"
shift 2 || shift $#
SEQS=("$@")
[ ${#SEQS[@]} -gt 0 ] || SEQS=(V1_01_easy V1_02_medium V1_03_difficult V2_01_easy V2_02_medium V2_03_difficult)
cd "$ROOT"
mkdir -p "$OUT"
printf "| sequence | duration | frames | map updates | ATE RMSE | ATE max | median ms/frame |\n|---|---|---|---|---|---|---|\n" > "$OUT.md.tmp"
for seq in "${SEQS[@]}"; do
  sim="$OUT/$seq/sim"
  if [ ! -s "$sim/gt.tum" ]; then
    "$BIN/sim-rawlog" "share/quasiloc/sim/$seq.ini" --set Simulation.output_dir="$sim" \
      --set Simulation.duration_s="$DURATION" --set Simulation.inspection_png=false > "$OUT/$seq.sim.log"
  fi
  "$BIN/quasiloc-track" config.ini --set Tracking.input_rawlog="$(ls "$sim"/*.rawlog | head -1)" \
    --set Tracking.calibration_ini="$sim/calib.ini" --set Tracking.map_file="$sim/lidar_map.map" \
    --set Tracking.groundtruth="$sim/gt.tum" --set Tracking.output_dir="$OUT/$seq/track" > "$OUT/$seq.track.log"
  summary="$OUT/$seq/track/summary.json"
  frames=$(/usr/bin/python3 scripts/json_figure.py "$summary" frames map_updates)
  ate=$(/usr/bin/python3 scripts/json_figure.py "$summary" ate.rmse_m ate.max_m --scale 100 --digits 3)
  ms=$(/usr/bin/python3 scripts/json_figure.py "$summary" time_per_frame_ms.median --digits 3)
  set -- $frames $ate
  duration_text="$DURATION s"; [ "$DURATION" != 0 ] || duration_text="whole"
  printf "| %s | %s | %s | %s | %s cm | %s cm | %s |\n" "$seq" "$duration_text" "$1" "$2" "$3" "$4" "$ms" | tee -a "$OUT.md.tmp"
done
mv "$OUT.md.tmp" "$OUT.md"
echo "table written to $OUT.md"
