#!/usr/bin/env bash
# Tracking against the map vs the baselines of issue 9, on the simulated sequences that scripts/track_sequences.sh
# left in <root> (reused, not simulated again): quasiloc-track with config.ini (IMU + map alignment + stereo
# landmarks) with the map as a pose measurement ([Tracking] map_term = measurement) whose information is uniform
# (map_information = fixed) or shaped by what the alignment observes (observability), the edge residuals as a
# factor in the window (map_term = factor, the default),
# visual-inertial odometry with the same front-end and no map
# ([Tracking] map_updates = false), and IMU-only propagation (map_updates = false, temporal_landmarks = false).
# All start from the same ground-truth state; the tracker is deterministic, so one run per cell.
#   bash scripts/track_baselines.sh [root=out/sequences] [out=out/baselines]
# Writes <out>/<seq>/<variant>/ (trajectory, diagnostics) and the table <out>.md (ATE RMSE / max, map frame, no
# alignment).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BIN="${QUASILOC_BUILD_DIR:-$ROOT/build}/bin"
SEQ_ROOT="${1:-out/sequences}"
OUT="${2:-out/baselines}"
cd "$ROOT"
mkdir -p "$OUT"
run() {  # run <seq> <variant> [--set ...]: prints "RMSE max" in cm
  local seq="$1" variant="$2"; shift 2
  local sim="$SEQ_ROOT/$seq/sim"
  "$BIN/quasiloc-track" config.ini --set Tracking.input_rawlog="$(ls "$sim"/*.rawlog | head -1)" \
    --set Tracking.calibration_ini="$sim/calib.ini" --set Tracking.map_file="$sim/lidar_map.map" \
    --set Tracking.groundtruth="$sim/gt.tum" --set Tracking.output_dir="$OUT/$seq/$variant" "$@" \
    > "$OUT/$seq/$variant.log" 2>&1
  sed -n 's/^ATE *RMSE \([0-9.]*\) cm, median [0-9.]* cm, max \([0-9.]*\) cm.*/\1 \2/p' "$OUT/$seq/$variant.log"
}
{
  echo "| sequence | map, uniform information RMSE / max cm | map, observability information RMSE / max cm | map, direct factor RMSE / max cm | VIO, no map RMSE / max cm | IMU only RMSE / max cm |"
  echo "|---|---|---|---|---|---|"
} > "$OUT.md.tmp"
for dir in "$SEQ_ROOT"/*/sim; do
  seq=$(basename "$(dirname "$dir")")
  mkdir -p "$OUT/$seq"
  set -- $(run "$seq" map_fixed --set Tracking.map_term=measurement --set Tracking.map_information=fixed) \
    $(run "$seq" map_observability --set Tracking.map_term=measurement --set Tracking.map_information=observability) \
    $(run "$seq" map_factor --set Tracking.map_term=factor) \
    $(run "$seq" vio --set Tracking.map_updates=false) \
    $(run "$seq" imu --set Tracking.map_updates=false --set Tracking.temporal_landmarks=false)
  printf "| %s | %s / %s | %s / %s | %s / %s | %s / %s | %s / %s |\n" "$seq" "$1" "$2" "$3" "$4" "$5" "$6" "$7" "$8" "$9" "${10}" \
    | tee -a "$OUT.md.tmp"
done
mv "$OUT.md.tmp" "$OUT.md"
echo "table written to $OUT.md"
