#!/usr/bin/env bash
# quasiloc on real EuRoC frames against the real room's geometry: the V1_01 micro set (95 real stereo frames, the
# real IMU, the MAV standing on the ground) converted by euroc2rawlog, a LidarMap sampled from the GMMLoc mixture of
# the Leica scan (map-import v1.gmm), then quasiloc-track with config.ini's tracker (init = global: no initial guess).
#   bash scripts/real_micro.sh [output_dir=out/real_micro] [--no-groundtruth] [--set Section.key=value]...
# Prints quasiloc-track's summary (start error, ATE against the ground truth, time per frame). With --no-groundtruth
# the run is given no ground truth, as on a user's own robot, and is scored afterwards from its files by quasiloc-eval
# (ATE unaligned and aligned, RPE). The rawlog and the map are reused when present. Needs a built tree
# (scripts/build.sh) and ../shared beside the repository.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BIN="${QUASILOC_BUILD_DIR:-$ROOT/build}/bin"
SHARED="${QUASILOC_SHARED_DIR:-$ROOT/../shared}"
OUT="${1:-out/real_micro}"
shift || true
GT_SET=(--set Tracking.groundtruth="$OUT/micro_gt_cam0.tum")
if [ "${1:-}" = "--no-groundtruth" ]; then GT_SET=(--set Tracking.groundtruth=); shift; fi
EUROC="$SHARED/data/euroc"
[ -d "$EUROC/V1_01_easy_micro" ] || { echo "error: $EUROC/V1_01_easy_micro not found (../shared/data)" >&2; exit 1; }
cd "$ROOT"
mkdir -p "$OUT"
if [ ! -s "$OUT/micro_calib.ini" ]; then
  "$BIN/euroc2rawlog" --input "$EUROC/V1_01_easy_micro" --output "$OUT/micro.rawlog" \
    --groundtruth "$EUROC/groundtruth/cam0/V1_01_easy.txt" > "$OUT/euroc2rawlog.log"
fi
if [ ! -s "$OUT/v1.map" ]; then
  "$BIN/map-import" --input "$EUROC/maps/gmm/v1.gmm" --output "$OUT/v1.map" > "$OUT/map-import.log"
fi
"$BIN/quasiloc-track" config.ini --set Tracking.input_rawlog="$OUT/micro.rawlog" \
  --set Tracking.calibration_ini="$OUT/micro_calib.ini" --set Tracking.map_file="$OUT/v1.map" \
  "${GT_SET[@]}" --set Tracking.output_dir="$OUT/track" \
  --set Initialization.init=global --set Tracking.write_scene=false "$@" > "$OUT/track.log" 2>&1 ||
  { tail -5 "$OUT/track.log" >&2; echo "error: quasiloc-track failed (log: $OUT/track.log)" >&2; exit 1; }
grep -E "^(init start error|IMU biases at the start|frames|ATE|time/frame|losses)" "$OUT/track.log" || true
echo "log: $OUT/track.log"
if [ "${GT_SET[1]}" = "Tracking.groundtruth=" ]; then
  # Scored from the files, the ground truth looked up as quasiloc-track would have (interpolated, within 5 ms).
  "$BIN/quasiloc-eval" --estimate "$OUT/track/trajectory.tum" --groundtruth "$OUT/micro_gt_cam0.tum" \
    --association interpolated --max-dt-s 0.005 --output-dir "$OUT/eval" > "$OUT/eval.log" 2>&1 ||
    { cat "$OUT/eval.log" >&2; echo "error: quasiloc-eval failed (log: $OUT/eval.log)" >&2; exit 1; }
  grep -E "^(## Tracking|\| trajectory )" "$OUT/eval.log" || true
  echo "scored: $OUT/eval/report.md"
fi
