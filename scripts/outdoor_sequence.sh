#!/usr/bin/env bash
# The simulated car on the outdoor campus (share/quasiloc/sim/campus_car.ini: KITTI-like stereo at 10 Hz, a 100 Hz
# automotive IMU with drawn biases, a map built from sweeps of every street): simulated once, then tracked with the
# top-level config.ini's tracker for each start given (global: no initial guess; groundtruth: from the true pose, to
# measure tracking alone), and one table (docs/benchmarks.md, "Outdoor campus, car rig (simulated)").
#   bash scripts/outdoor_sequence.sh [output_root=out/campus] [duration_s=60] [starts...=global groundtruth]
# Environment: CAMPUS_SIM_SET (more sim-rawlog overrides, e.g. the campus's size), CAMPUS_TRACK_SET (more tracker
# overrides, e.g. "--config share/quasiloc/outdoor.ini" settings). The simulated folder is reused when present.
# Columns: ATE RMSE over every logged pose (map frame, no alignment, quasiloc-track's summary); max verified: the
# largest error of a frame neither lost nor flagged unverified; losses and unverified frames: the tracker's counts;
# start: the initialization's error; wall ms/frame: the tracker's median / p95; CPU ms/frame: (user + sys) of the
# whole run over the frames; peak RSS and map load (points, field) from /usr/bin/time and the summary.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BIN="${QUASILOC_BUILD_DIR:-$ROOT/build}/bin"
OUT="${1:-out/campus}"
DURATION="${2:-60}"
shift 2 || shift $#
STARTS=("$@")
[ ${#STARTS[@]} -gt 0 ] || STARTS=(global groundtruth)
cd "$ROOT"
mkdir -p "$OUT"
read -r -a sim_extra <<< "${CAMPUS_SIM_SET:-}"
read -r -a track_extra <<< "${CAMPUS_TRACK_SET:-}"
sim="$OUT/sim"
if [ ! -s "$sim/gt.tum" ]; then
  /usr/bin/time -f "%U %S %e %M" -o "$OUT/sim.time" "$BIN/sim-rawlog" share/quasiloc/sim/campus_car.ini \
    --set Simulation.output_dir="$sim" --set Simulation.duration_s="$DURATION" "${sim_extra[@]}" > "$OUT/sim.log"
fi
for start in "${STARTS[@]}"; do
  /usr/bin/time -f "%U %S %e %M" -o "$OUT/$start.time" "$BIN/quasiloc-track" config.ini \
    --set Tracking.input_rawlog="$sim/campus_car.rawlog" --set Tracking.calibration_ini="$sim/calib.ini" \
    --set Tracking.map_file="$sim/lidar_map.map" --set Tracking.groundtruth="$sim/gt.tum" \
    --set Tracking.output_dir="$OUT/$start/track" --set Initialization.init="$start" --set Tracking.write_scene=false \
    "${track_extra[@]}" > "$OUT/$start.track.log" 2>&1 || echo "quasiloc-track ($start) failed: $OUT/$start.track.log"
done
/usr/bin/python3 - "$OUT" "$(cut -d' ' -f1-3 /proc/loadavg)" "${STARTS[@]}" <<'PY' | tee "$OUT.md"
import csv, json, math, os, sys
out, load, starts = sys.argv[1], sys.argv[2], sys.argv[3:]
u, s_, wall, rss = open(f"{out}/sim.time").read().split()[-4:] if os.path.exists(f"{out}/sim.time") else ("0",) * 4
print(f"Simulated car on the outdoor campus (share/quasiloc/sim/campus_car.ini), tracked with config.ini; simulation "
      f"{float(wall):.0f} s wall, peak RSS {int(rss) / 1e6:.2f} GB; load average at the end: {load}.\n")
print("| start | frames | ATE RMSE | max verified | losses | unverified | start error | wall ms/frame median / p95 "
      "| CPU ms/frame | peak RSS | map points / field |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for start in starts:
    path = f"{out}/{start}/track/summary.json"
    if not os.path.exists(path):
        print(f"| {start} | failed: see {out}/{start}.track.log |||||||||| ")
        continue
    s = json.load(open(path))
    worst = 0.0
    with open(f"{out}/{start}/track/diagnostics.csv") as f:
        for row in csv.DictReader(f):
            e = float(row["error_m"])
            if row["lost"] == "0" and row.get("unverified", "0") == "0" and math.isfinite(e):
                worst = max(worst, e)
    user, sys_s, wall, rss = (float(v) for v in open(f"{out}/{start}.time").read().split()[-4:])
    st, t, m = s["start"], s["time_per_frame_ms"], s["map"]
    print(f"| {start} | {s['frames']} | {s['ate']['rmse_m'] * 100:.2f} cm | {worst * 100:.2f} cm | {s['losses']} | "
          f"{s['frames_unverified']} | {st['error_m'] * 100:.2f} cm / {st['error_deg']:.2f} deg | "
          f"{t['median']:.1f} / {t['p95']:.1f} | {(user + sys_s) * 1e3 / s['frames']:.1f} | {rss / 1e6:.2f} GB | "
          f"{m['points'] / 1e6:.1f} M / {m['field_layout']} {m['field_mb']:.0f} MB in {m['field_s']:.1f} s |")
PY
