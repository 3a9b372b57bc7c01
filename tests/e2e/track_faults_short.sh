# quasiloc-track on a 6 s simulated V1_01 flight with injected sensor faults ([FaultInjection], docs/reliability.md):
# an IMU gap of 1 s, a duplicated and an out-of-order timestamp and a 0.5 s burst of dropped frames in one run; black
# images for 1 s and then a 20 ms left/right desync in another. Each run must end normally and report every rejected
# frame; no pose may be more than 10 cm off without the diagnostics flagging it unverified, and the track must be back
# within 3 cm of the truth within 2 s after each fault ends. The desync must be caught by the tracker's stereo check
# (TrackMonitor.stereo_check_max_sigmas). scripts/fault_table.py runs every fault on the six 30 s sequences.
source "$(dirname "$0")/common.sh"
SIM="$WORK/sim"
"$BIN/sim-rawlog" config.ini --set Simulation.output_dir="$SIM" --set Simulation.duration_s=6 \
  --set Simulation.inspection_png=false "${EXACT_MAP[@]}" > "$WORK/sim.txt"
F=FaultInjection
track() {  # track <output_dir> [--set ...]: from the ground truth, every relocalization attempt in order
  local out="$1"; shift
  "$BIN/quasiloc-track-harness" config.ini --set Tracking.input_rawlog="$SIM/V1_01_easy.rawlog" \
    --set Tracking.calibration_ini="$SIM/calib.ini" --set Tracking.map_file="$SIM/lidar_map.map" \
    --set Tracking.groundtruth="$SIM/gt.tum" --set Tracking.output_dir="$out" --set Tracking.write_scene=false \
    --set Initialization.init=groundtruth --set Relocalization.relocalize_latest_only=false "$@" > "$out.log" 2>&1 \
    || { cat "$out.log"; fail "quasiloc-track failed (exit $?) with faults $*"; }
  grep -v '^reloc\|^init' "$out.log"
}
# targets <output_dir> <until s> <fault end s>...: the largest error not flagged unverified before <until> and the
# time back within 3 cm after each fault's end.
targets() {
  /usr/bin/python3 - "$@" <<'PY' || fail "targets missed in $1"
import csv, json, math, sys
d, until, ends = sys.argv[1], float(sys.argv[2]), [float(x) for x in sys.argv[3:]]
s = json.load(open(d + "/summary.json"))
t0 = s["start"]["first_frame_t"]
rows = [(float(r["t"]) - t0, float(r["error_m"]), r["unverified"] == "1") for r in csv.DictReader(open(d + "/diagnostics.csv"))]
unflagged = max(e for t, e, u in rows if not u and t < until)
back = [min([t - end for t, e, _ in rows if t >= end and e <= 0.03], default=math.inf) for end in ends]
print("%s: ATE RMSE %.2f cm, %d frames unverified, largest unflagged error %.2f cm, back within 3 cm after %s s" % (
    d.split("/")[-1], 100 * s["ate"]["rmse_m"], s["frames_unverified"], 100 * unflagged,
    ", ".join("%.2f" % b for b in back)))
assert unflagged <= 0.10, "a pose %.1f cm off is not flagged unverified" % (100 * unflagged)
assert all(b <= 2.0 for b in back), "not back within 3 cm within 2 s of a fault's end"
PY
}
track "$WORK/timing" --set $F.imu_gap_from_s=1.5 --set $F.imu_gap_duration_s=1 --set $F.duplicate_at_s=3 \
  --set $F.reorder_at_s=3.5 --set $F.drop_from_s=3.8 --set $F.drop_duration_s=0.5
expect_contains "$WORK/timing.log" "rejected: no IMU sample since the previous frame"
expect_contains "$WORK/timing.log" "rejected: duplicated timestamp"
expect_contains "$WORK/timing.log" "rejected: timestamp earlier than the previous frame's"
targets "$WORK/timing" 1e9 2.5 3.05 3.6 4.3
track "$WORK/images" --set $F.image_fault=black --set $F.image_from_s=1.5 --set $F.image_duration_s=1 \
  --set $F.desync_from_s=4.5 --set $F.desync_duration_s=1 --set $F.desync_ms=20
expect_contains "$WORK/images.log" "injected fault: black images: 20 frame(s)"
expect_contains "$WORK/images.log" "injected fault: right image turned as desync_ms later: 20 frame(s)"
expect_contains "$WORK/images.log" "stereo left out, frames unverified"
targets "$WORK/images" 1e9 2.5 5.5
echo "OK"
