#!/usr/bin/env bash
# The simulated ground robot (share/quasiloc/sim/robot_floor.ini: D435i rig, BMI055 IMU, an office floor): for each
# seed, a sequence started standing and one started moving, each simulated then tracked with the top-level
# config.ini's tracker (init = global), and one table of the figures the ground-robot targets are set for (docs/benchmarks.md).
#   bash scripts/robot_sequences.sh [output_root=out/robot] [duration_s=30] [seeds...=1 2 3]
# Simulated folders are reused when present (delete them to simulate again); the table's map column says whether a
# folder's map was built from simulated sweeps (the default) or sampled exactly. Needs a built tree (scripts/build.sh).
# Tracker overrides (the rig differs from the simulated EuRoC one, the tracker does not): temporal_max_gap_s = 0.05
# (no temporal landmarks across a dropped frame of this 30 Hz camera, as config.ini's 0.1 s does at 20 Hz), no scene
# file. Columns:
#   ATE: RMSE over every logged pose, map frame, no alignment (quasiloc-track's summary);
#   max verified: the largest position error of a frame neither lost nor flagged unverified (diagnostics.csv);
#   losses, unverified frames: the tracker's own counts; start: the global initialization's error;
#   wall ms/frame: median and p95 of the tracker's per-frame time; CPU ms/frame: (user + sys) of the whole run
#   (map loading and the start's search included) over the frames, from /usr/bin/time.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BIN="${QUASILOC_BUILD_DIR:-$ROOT/build}/bin"
OUT="${1:-out/robot}"
DURATION="${2:-30}"
shift 2 || shift $#
SEEDS=("$@")
[ ${#SEEDS[@]} -gt 0 ] || SEEDS=(1 2 3)
cd "$ROOT"
mkdir -p "$OUT"
TRACK_SET=(--set Tracking.temporal_max_gap_s=0.05 --set Tracking.write_scene=false)
# More tracker overrides from the environment, e.g. a lever of docs/benchmarks.md:
#   ROBOT_TRACK_SET="--set TrackMonitor.odometry_while_lost=true --set Relocalization.relocalize_odometry_drift_ratio=0.2"
read -r -a extra <<< "${ROBOT_TRACK_SET:-}"
TRACK_SET+=("${extra[@]}")
runs=()
for seed in "${SEEDS[@]}"; do
  for start in standing moving; do
    name="seed${seed}_${start}"
    sim="$OUT/$name/sim"
    moving=false; [ "$start" = moving ] && moving=true
    if [ ! -s "$sim/gt.tum" ]; then
      "$BIN/sim-rawlog" share/quasiloc/sim/robot_floor.ini --set Simulation.output_dir="$sim" \
        --set Simulation.seed="$seed" --set IMU.seed="$seed" --set Simulation.duration_s="$DURATION" \
        --set Simulation.robot_start_moving="$moving" --set Simulation.inspection_png=false > "$OUT/$name.sim.log"
    fi
    /usr/bin/time -f "%U %S %e" -o "$OUT/$name.time" "$BIN/quasiloc-track" config.ini \
      --set Tracking.input_rawlog="$sim/robot_floor.rawlog" --set Tracking.calibration_ini="$sim/calib.ini" \
      --set Tracking.map_file="$sim/lidar_map.map" --set Tracking.groundtruth="$sim/gt.tum" \
      --set Tracking.output_dir="$OUT/$name/track" "${TRACK_SET[@]}" > "$OUT/$name.track.log"
    runs+=("$name")
  done
done
/usr/bin/python3 - "$OUT" "$(cut -d' ' -f1-3 /proc/loadavg)" "${TRACK_SET[*]}" "${runs[@]}" <<'EOF' | tee "$OUT.md"
import csv, json, math, sys
out, load, overrides, runs = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
print(f"Simulated ground robot (D435i-like rig, 30 Hz; share/quasiloc/sim/robot_floor.ini), tracked with config.ini "
      f"and {overrides}; load average at the end: {load}.\n")
print("| run | map | frames | ATE RMSE | max verified | losses | unverified | start error | wall ms/frame median / p95 "
      "| CPU ms/frame | map updates |")
print("|---|---|---|---|---|---|---|---|---|---|---|")


def map_source(name):
    # The map the folder was simulated with (folders made before swept maps were the default hold exact ones).
    for line in open(f"{out}/{name}/sim/sim-rawlog.ini"):
        key, _, value = line.partition("=")
        if key.strip() == "map_source":
            return "swept" if value.split()[0] == "sweeps" else "exact"
    return "exact"


for name in runs:
    s = json.load(open(f"{out}/{name}/track/summary.json"))
    worst = 0.0
    with open(f"{out}/{name}/track/diagnostics.csv") as f:
        for row in csv.DictReader(f):
            e = float(row["error_m"])
            if row["lost"] == "0" and row.get("unverified", "0") == "0" and math.isfinite(e):
                worst = max(worst, e)
    user, sys_s, wall = (float(v) for v in open(f"{out}/{name}.time").read().split()[-3:])
    cpu = (user + sys_s) * 1e3 / s["frames"]
    st, t = s["start"], s["time_per_frame_ms"]
    print(f"| {name} | {map_source(name)} | {s['frames']} | {s['ate']['rmse_m'] * 100:.2f} cm | {worst * 100:.2f} cm | {s['losses']} | "
          f"{s['frames_unverified']} | {st['error_m'] * 100:.2f} cm / {st['error_deg']:.2f} deg | "
          f"{t['median']:.1f} / {t['p95']:.1f} | {cpu:.1f} | {s['map_updates']} |")
EOF
echo "table written to $OUT.md"
