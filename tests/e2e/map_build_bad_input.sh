# map-build's bad inputs: each is an error naming the file (or key) and what is wrong, a non-zero exit, and nothing
# written (no map, no effective config, no temporary).
source "$(dirname "$0")/common.sh"
DATA="$SHARED/data/kitti_raw_seq78"
mkdir -p "$WORK/scans"
for f in 0 2 4; do ln -s "$DATA/velodyne_even/$(printf %010d $f).bin" "$WORK/scans/"; done
head -n 7 "$DATA/poses_cam2.txt" > "$WORK/poses.txt"  # the comment line, then frames 0..5
printf '[MapBuild]\nscan_folder = %s\ntrajectory = %s\ntrajectory_format = kitti\nextrinsic_file = %s\nextrinsic_key = T_cam2rect_velo\noutput = %s\n' \
  "$WORK/scans" "$WORK/poses.txt" "$DATA/calib.txt" "$WORK/out/map.map" > "$WORK/ok.ini"
"$BIN/map-build" "$WORK/ok.ini" > "$WORK/ok.log" || { cat "$WORK/ok.log"; fail "the good input failed"; }
rm -rf "$WORK/out"
check_rejected() {  # check_rejected <what> <text the error must hold> [--set ...]
  local what="$1" text="$2"; shift 2
  expect_failure "$WORK/log.txt" "$BIN/map-build" "$WORK/ok.ini" "$@"
  expect_contains "$WORK/log.txt" "$text"
  [ ! -e "$WORK/out" ] || [ -z "$(ls -A "$WORK/out")" ] || fail "output left behind for $what: $(ls -A "$WORK/out")"
  echo "rejected ($what): $(tail -1 "$WORK/log.txt")"
}
# A scan that does not parse (truncated record), then one with a NaN coordinate.
mkdir -p "$WORK/bad1" "$WORK/bad2"
cp "$WORK/scans/"*.bin "$WORK/bad1/"; head -c 100 "$DATA/velodyne_even/0000000002.bin" > "$WORK/bad1/0000000002.bin"
check_rejected "truncated scan" "0000000002.bin: truncated KITTI .bin" --set MapBuild.scan_folder="$WORK/bad1"
cp "$WORK/scans/"*.bin "$WORK/bad2/"; rm "$WORK/bad2/0000000004.bin"
/usr/bin/python3 -c "
import numpy as np, sys
a = np.fromfile('$DATA/velodyne_even/0000000004.bin', '<f4').reshape(-1, 4); a[500, 1] = np.nan
a.tofile('$WORK/bad2/0000000004.bin')"
check_rejected "NaN point" "0000000004.bin: point 500 has a non-finite" --set MapBuild.scan_folder="$WORK/bad2"
# A trajectory with fewer poses than the scans need; a TUM trajectory that does not cover a scan's time.
head -n 4 "$DATA/poses_cam2.txt" > "$WORK/short.txt"
check_rejected "too few poses" "0000000004.bin: needs pose line 5" --set MapBuild.trajectory="$WORK/short.txt"
printf '0 0 0 0 0 0 0 1\n0.3 1 0 0 0 0 0 1\n' > "$WORK/traj.tum"
check_rejected "trajectory does not cover" "0000000002.bin: its time 2 s has no pose" \
  --set MapBuild.trajectory="$WORK/traj.tum" --set MapBuild.trajectory_format=tum
# Options: a typo'd key, an extrinsic that is not there, a bag source without its bag (bags' own bad inputs:
# map_build_bag_bad_input.sh).
check_rejected "unknown key" "[MapBuild] voxel_size: unknown key" --set MapBuild.voxel_size=0.1
check_rejected "missing extrinsic" "calib.txt: no line 'T_lidar: ...'" --set MapBuild.extrinsic_key=T_lidar
check_rejected "bag source without a bag" "[MapBuild] bag: is required with source = bag" --set MapBuild.source=bag
check_rejected "no scans" "holds no scan file" --set MapBuild.scan_folder="$WORK"
echo "OK"
