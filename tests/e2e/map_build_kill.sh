# A map-build killed midway leaves no half-written output: map-build (12 KITTI scans, with exports) is SIGKILLed
# at seeded random times, each run into a fresh folder; every output present must then be byte for byte a full run's
# (the effective configuration: its line count, it names the folder), the map present must mean all outputs are,
# and nothing but outputs and hidden temporaries may be there. KILLS (default 4), SEED (default 40).
source "$(dirname "$0")/common.sh"
KILLS="${KILLS:-4}"
RANDOM="${SEED:-40}"
DATA="$SHARED/data/kitti_raw_seq78"
mkdir -p "$WORK/scans"
for f in $(seq 0 2 22); do ln -s "$DATA/velodyne_even/$(printf %010d $f).bin" "$WORK/scans/"; done
build() {  # build <output_dir>
  exec "$BIN/map-build" rawlog_tools/map-build/kitti_raw_seq78.ini --set MapBuild.scan_folder="$WORK/scans" \
    --set MapBuild.trajectory="$DATA/poses_cam2.txt" --set MapBuild.extrinsic_file="$DATA/calib.txt" \
    --set MapBuild.output="$1/kitti.map" --set MapBuild.export_cloud="$1/kitti.ply" \
    --set MapBuild.export_removed="$1/removed.ply"
}
OUTPUTS="kitti.map kitti.ply removed.ply kitti.map.ini"
check() {  # check <dir>
  /usr/bin/python3 - "$1" "$WORK/ref" $OUTPUTS <<'PY' || fail "incomplete output in $1"
import filecmp, os, re, sys
d, ref, outputs = sys.argv[1], sys.argv[2], sys.argv[3:]
temp = re.compile(r"^\.+.*\.tmp-\d+-[0-9a-f]+")
present = os.listdir(d) if os.path.isdir(d) else []
assert not [f for f in present if f not in outputs and not temp.match(f)], "unexpected files %s" % present
for f in outputs:
    p = os.path.join(d, f)
    if not os.path.exists(p):
        assert not os.path.exists(os.path.join(d, "kitti.map")), "kitti.map is there but %s is not" % f
    elif f.endswith(".ini"):
        assert len(open(p).readlines()) == len(open(os.path.join(ref, f)).readlines()), f + " incomplete"
    else:
        assert filecmp.cmp(p, os.path.join(ref, f), shallow=False), f + " differs from the full run's"
print("%d of %d outputs present, complete; %d temporaries" % (
    sum(os.path.exists(os.path.join(d, f)) for f in outputs), len(outputs), sum(bool(temp.match(f)) for f in present)))
PY
}
t0=$(date +%s%N)
(build "$WORK/ref") > "$WORK/ref.log" 2>&1 || { cat "$WORK/ref.log"; fail "map-build failed"; }
full_ms=$(( ($(date +%s%N) - t0) / 1000000 ))
for ((k = 0; k < KILLS; ++k)); do
  at_ms=$(( k % 2 == 0 ? RANDOM % (full_ms + 1) : full_ms * 9 / 10 + RANDOM % (full_ms / 10 + 1) ))
  dir="$WORK/kill$k"
  (build "$dir") > "$dir.log" 2>&1 &
  pid=$!
  sleep "$(awk -v m="$at_ms" 'BEGIN { printf "%.3f", m / 1000 }')"
  kill -9 "$pid" 2>/dev/null || true
  wait "$pid" 2>/dev/null || true
  echo -n "killed at $at_ms of $full_ms ms: "
  check "$dir"
done
# A full run into the last killed run's folder: leftovers removed, outputs complete.
(build "$dir") > "$dir.rerun.log" 2>&1 || { cat "$dir.rerun.log"; fail "map-build failed after a kill"; }
echo -n "full run after the kills: "
check "$dir"
[ -z "$(ls -A "$dir" | grep '\.tmp-' || true)" ] || fail "temporaries left after a full run: $(ls -A "$dir")"
echo "OK"
