#!/usr/bin/env bash
# The main job on the built-in simulated world, as configured by config.ini:
# set-up and build, then generate the simulated sequence (LiDAR map, stereo + IMU rawlog, ground truth),
# then every later stage of the pipeline that exists.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BIN="${QUASILOC_BUILD_DIR:-$ROOT/build}/bin"
CONFIG="${1:-$ROOT/config.ini}"
shift || true

bash "$ROOT/scripts/build.sh"
cd "$ROOT"

echo "== sim-rawlog: simulated world, LiDAR map, stereo images, IMU, ground truth"
"$BIN/sim-rawlog" "$CONFIG" "$@"
SIM_DIR="$(sed -n 's/^output_dir *= *//p' "$CONFIG" | head -1)"
RAWLOG="$(ls "$SIM_DIR"/*.rawlog | head -1)"

echo "== rawlog-edit --info (MRPT reads what we wrote)"
(cd "$(dirname "$RAWLOG")" && rawlog-edit --info -i "$(basename "$RAWLOG")" 2>&1 | grep -E "objects|labels|Sensor")

echo "== rawlog-quasi: quasi-images with provenance at every ground-truth pose"
"$BIN/rawlog-quasi" "$CONFIG"

echo "== quasiloc-track: global localization by geometry (no initial guess), then stereo-inertial tracking against the LiDAR map"
"$BIN/quasiloc-track" "$CONFIG"
TRACK_DIR="$(sed -n '/^\[Tracking\]/,/^\[/s/^output_dir *= *//p' "$CONFIG" | head -1)"
echo "== plots: top view against the ground truth, error and time per stage over time"
/usr/bin/python3 "$ROOT/share/quasiloc/plot_tracking.py" "$TRACK_DIR" "$SIM_DIR/gt.tum"

# Global localization (no initial guess) from a database rendered from the LiDAR map alone. Its own INI: the
# database's quasi-images use map-wide reflectivity normalisation, the tracker's per-image normalisation.
RELOC_INI="$ROOT/share/quasiloc/reloc/sim_room.ini"
DB="out/reloc/$(basename "$SIM_DIR")/room.qdb"
echo "== quasiloc-build-db: database of virtual views of the whole room"
"$BIN/quasiloc-build-db" "$RELOC_INI" --set BuildDatabase.map_file="$SIM_DIR/lidar_map.map" \
  --set BuildDatabase.calibration_ini="$SIM_DIR/calib.ini" --set BuildDatabase.output="$DB"
for query in camera quasi; do
  echo "== quasiloc-localize: every 10th $query image (quasi: the map rendered at the true pose, no modality gap)"
  "$BIN/quasiloc-localize" "$RELOC_INI" --set Localize.database="$DB" --set Localize.input_rawlog="$RAWLOG" \
    --set Localize.groundtruth="$SIM_DIR/gt.tum" --set Localize.map_file="$SIM_DIR/lidar_map.map" \
    --set Localize.query_image=$query --set Localize.output_dir="$(dirname "$DB")/localize_$query" | sed -n '/^# quasiloc-localize summary/,$p'
done

echo "== done: outputs in $SIM_DIR, out/quasi (open the rawlogs with RawLogViewer), out/track and out/reloc"
