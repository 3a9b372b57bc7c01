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

echo "== quasiloc-track: stereo-inertial tracking against the LiDAR map (IMU + direct map alignment)"
"$BIN/quasiloc-track" "$CONFIG"

echo "== done: outputs in $SIM_DIR, out/quasi (open the rawlogs with RawLogViewer) and out/track"
