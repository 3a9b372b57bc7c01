# Nothing half-written, also when a program is killed (docs/reliability.md): quasiloc-build-db,
# quasiloc-track and map-import are SIGKILLed at seeded random times while they run, each into a fresh output
# folder; then every output present must be complete (byte for byte a full run's, or, for the files that hold
# timings, parsing with the full run's number of rows), the main output present must mean all are present (commit
# renames it last), and no file but the outputs and hidden temporaries ".<name>.tmp-<pid>-<random>" may be there.
# Finally a full run into a killed run's folder must remove those temporaries and write complete outputs.
#   KILLS (default 4): kills per program; SEED (default 25). The long version: KILLS=20 bash <this> build/bin <shared>
source "$(dirname "$0")/common.sh"
KILLS="${KILLS:-4}"
RANDOM="${SEED:-25}"
SIM="$WORK/sim"
"$BIN/sim-rawlog" config.ini --set Simulation.output_dir="$SIM" --set Simulation.duration_s=3 \
  --set Simulation.inspection_png=false "${EXACT_MAP[@]}" > "$WORK/sim.txt"

# The programs, each exec'ed (run them in a subshell or under bash -c) so that the kill reaches the program itself.
build_db() {  # build_db <output_dir>
  exec "$BIN/quasiloc-build-db" share/quasiloc/reloc/sim_room.ini --set BuildDatabase.map_file="$SIM/lidar_map.map" \
    --set BuildDatabase.calibration_ini="$SIM/calib.ini" --set BuildDatabase.output="$1/room.qdb" \
    --set ViewSampling.region="0.3 1.7 2.3 2.9"
}
track() {  # track <output_dir>: reproducible (ground-truth start, every relocalization attempt in order)
  exec "$BIN/quasiloc-track" config.ini --set Tracking.input_rawlog="$SIM/V1_01_easy.rawlog" \
    --set Tracking.calibration_ini="$SIM/calib.ini" --set Tracking.map_file="$SIM/lidar_map.map" \
    --set Tracking.groundtruth="$SIM/gt.tum" --set Tracking.output_dir="$1" --set Initialization.init=groundtruth \
    --set Relocalization.relocalize_latest_only=false
}
map_import() {  # map_import <output_dir>
  exec "$BIN/map-import" --input "$SHARED/data/kitti_raw_seq78/map_even_frames_5cm.ply" --output "$1/kitti.map" \
    --export "$1/kitti.ply"
}

# check <program> <dir> <reference_dir> <main output> <outputs...>: every output present is complete.
check() {
  /usr/bin/python3 - "$@" <<'PY' || fail "$1: incomplete output in $2 (see above)"
import filecmp, json, os, re, sys
prog, d, ref, main, outputs = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5:]
temp = re.compile(r"^\.+.*\.tmp-\d+-[0-9a-f]+")
present = [f for f in os.listdir(d)] if os.path.isdir(d) else []
bad = [f for f in present if f not in outputs and not temp.match(f)]
assert not bad, "%s: unexpected files %s" % (prog, bad)
def rows(path):
    with open(path) as f:
        return [line for line in f.read().split("\n") if line]
for f in outputs:
    p, r = os.path.join(d, f), os.path.join(ref, f)
    if not os.path.exists(p):
        assert not os.path.exists(os.path.join(d, main)), "%s: %s is there but %s is not" % (prog, main, f)
        continue
    if f == "summary.json":
        a, b = json.load(open(p)), json.load(open(r))
        assert a["frames"] == b["frames"] and a.keys() == b.keys(), "%s: summary.json differs" % prog
    elif f.endswith(".ini") or f in ("diagnostics.csv", "initialization.txt"):  # output paths, timings
        a, b = rows(p), rows(r)
        assert len(a) == len(b) and open(p).read().endswith("\n"), "%s: %s has %d lines, the full run's %d" % (
            prog, f, len(a), len(b))
        assert all(x.count(",") == a[0].count(",") for x in a) or f != "diagnostics.csv", "ragged " + f
    else:
        assert filecmp.cmp(p, r, shallow=False), "%s: %s differs from the full run's" % (prog, f)
print("%s: %s: %d of %d outputs present, complete; %d temporaries" % (
    prog, os.path.basename(d), sum(os.path.exists(os.path.join(d, f)) for f in outputs), len(outputs),
    sum(bool(temp.match(f)) for f in present)))
PY
}

# kill_test <program function> <main output> <outputs...>
kill_test() {
  local prog="$1"; shift
  local t0=$(date +%s%N)
  ("$prog" "$WORK/$prog.ref") > "$WORK/$prog.ref.log" 2>&1 || { cat "$WORK/$prog.ref.log"; fail "$prog failed"; }
  local full_ms=$(( ($(date +%s%N) - t0) / 1000000 ))
  for ((k = 0; k < KILLS; ++k)); do
    # Half the kills anywhere in a full run's time, half in its last tenth (where the outputs are written).
    local at_ms=$(( k % 2 == 0 ? RANDOM % (full_ms + 1) : full_ms * 9 / 10 + RANDOM % (full_ms / 10 + 1) ))
    local dir="$WORK/$prog.kill$k"
    # The subshell execs the program (same pid): kill -9 reaches it, and wait reaps it before the folder is read.
    ("$prog" "$dir") > "$dir.log" 2>&1 &
    local pid=$!
    sleep "$(awk -v m="$at_ms" 'BEGIN { printf "%.3f", m / 1000 }')"
    kill -9 "$pid" 2>/dev/null || true
    wait "$pid" 2>/dev/null || true
    echo -n "killed at $at_ms of $full_ms ms: "
    check "$prog" "$dir" "$WORK/$prog.ref" "$@"
  done
  # A full run into a killed run's folder (one with temporaries, if any): leftovers removed, outputs complete.
  local dir="$WORK/$prog.kill$((KILLS - 1))"
  for ((k = 0; k < KILLS; ++k)); do
    if ls -A "$WORK/$prog.kill$k" 2>/dev/null | grep -q '\.tmp-'; then dir="$WORK/$prog.kill$k"; break; fi
  done
  ("$prog" "$dir") > "$dir.rerun.log" 2>&1 || { cat "$dir.rerun.log"; fail "$prog failed after a kill"; }
  echo -n "full run after the kills: "
  check "$prog" "$dir" "$WORK/$prog.ref" "$@"
  [ -z "$(ls -A "$dir" | grep '\.tmp-' || true)" ] || fail "$prog: temporaries left after a full run: $(ls -A "$dir")"
}

kill_test build_db room.qdb room.qdb room.qdb.views.tum room.qdb.ini
kill_test map_import kitti.map kitti.map kitti.ply kitti.map.ini
kill_test track trajectory.tum trajectory.tum diagnostics.csv summary.json quasiloc-track.ini initialization.txt \
  scene.3Dscene
echo "OK"
