# map-build on 8 real KITTI scans (frames 0, 10, ..., 70 of ../shared/data/kitti_raw_seq78, spanning the ego car's
# creep through the traffic queue): built with and without carving. The carving must remove points in the vehicle
# corridor (above the road, within the lanes) and keep the road; the exports must match the map.
source "$(dirname "$0")/common.sh"
DATA="$SHARED/data/kitti_raw_seq78"
mkdir -p "$WORK/scans"
for f in 0 10 20 30 40 50 60 70; do ln -s "$DATA/velodyne_even/$(printf %010d $f).bin" "$WORK/scans/"; done
run_build() {  # run_build <name> [--set ...]
  local name="$1"; shift
  "$BIN/map-build" rawlog_tools/map-build/kitti_raw_seq78.ini --set MapBuild.scan_folder="$WORK/scans" \
    --set MapBuild.trajectory="$DATA/poses_cam2.txt" --set MapBuild.extrinsic_file="$DATA/calib.txt" \
    --set MapBuild.output="$WORK/$name.map" --set MapBuild.export_cloud="$WORK/$name.ply" "$@" > "$WORK/$name.log" \
    || { cat "$WORK/$name.log"; fail "map-build $name failed"; }
}
run_build carved --set MapBuild.export_removed="$WORK/removed.ply"
run_build uncarved --set MapBuild.carve=false
expect_contains "$WORK/carved.log" "pass 2 (carve) 8/8 scans"
expect_contains "$WORK/carved.log" "0 of 8 scans deskewed"
grep -E "^carving +[0-9]+ of" "$WORK/carved.log" || fail "no carving line"
[ -s "$WORK/carved.map" ] && [ -s "$WORK/carved.map.ini" ] && [ -s "$WORK/removed.ply" ] || fail "missing outputs"
/usr/bin/python3 - "$WORK" "$DATA" <<'PY' || fail "carving check failed (see above)"
import os, sys
import numpy as np
sys.path.insert(0, "scripts")
import kitti_map_build_check as c
import kitti_map_check as k
work, data = sys.argv[1], sys.argv[2]
U, _ = k.load_ply_xyzi(os.path.join(work, "uncarved.ply"))
C, _ = k.load_ply_xyzi(os.path.join(work, "carved.ply"))
R, _ = k.load_ply_xyzi(os.path.join(work, "removed.ply"))
assert len(C) + len(R) == len(U), "carved + removed != uncarved: %d + %d != %d" % (len(C), len(R), len(U))
height = c.road_table(U)
cam = np.array([T[:3, 3] for T in k.load_poses(os.path.join(data, "poses_cam2.txt"))])
_, veh_u = c.regions(U, height, cam)
_, veh_c = c.regions(C, height, cam)
y = np.median(cam[:, 1])
def road(P):
    h = height(P)
    return (np.abs(P[:, 1] - y) < c.CORRIDOR_HALF_WIDTH_M) & (np.abs(h) < 0.15)
removed_vehicle = 1 - veh_c.sum() / veh_u.sum()
kept_road = road(C).sum() / road(U).sum()
print("vehicle corridor: %d -> %d points (%.1f %% removed); road: %d -> %d (%.2f %% kept)" % (
    veh_u.sum(), veh_c.sum(), 100 * removed_vehicle, road(U).sum(), road(C).sum(), 100 * kept_road))
assert removed_vehicle > 0.05, "the carving removed too little of the vehicle corridor"
assert kept_road > 0.98, "the carving removed road"
PY
echo "OK"
