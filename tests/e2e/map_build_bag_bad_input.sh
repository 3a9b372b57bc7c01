# map-build's bad bag inputs: a bag without the topic, a topic of another type, a PointCloud2 without x/y/z, a
# truncated point buffer, a pose topic of another type, a missing bag. Each is an error naming the bag, the topic
# and (for a message) its index, a non-zero exit, and nothing written. In a ROS 2 MCAP bag, and in a ROS 1 bag where
# this build has them.
source "$(dirname "$0")/common.sh"
DATA="$SHARED/data/kitti_raw_seq78"
mkdir -p "$WORK/scans"
for f in 0 2 4; do ln -s "$DATA/velodyne_even/$(printf %010d $f).bin" "$WORK/scans/"; done
printf '1317000000.000000000\n1317000000.200000000\n1317000000.400000000\n' > "$WORK/times.txt"
printf '1317000000 0 0 0 0 0 0 1\n1317000001 1 0 0 0 0 0 1\n' > "$WORK/traj.tum"
printf '[MapBuild]\nsource = bag\nbag_lidar_topic = /points\ntrajectory = %s\nmax_pose_gap_s = 2\nextrinsic_file = %s\nextrinsic_key = T_cam2rect_velo\noutput = %s\n' \
  "$WORK/traj.tum" "$DATA/calib.txt" "$WORK/out/map.map" > "$WORK/ok.ini"
check_rejected() {  # check_rejected <what> <text the error must hold> [--set ...]
  local what="$1" text="$2"; shift 2
  expect_failure "$WORK/log.txt" "$BIN/map-build" "$WORK/ok.ini" "$@"
  expect_contains "$WORK/log.txt" "$text"
  [ ! -e "$WORK/out" ] || [ -z "$(ls -A "$WORK/out")" ] || fail "output left behind for $what: $(ls -A "$WORK/out")"
  echo "rejected ($what): $(tail -1 "$WORK/log.txt")"
}
formats=(mcap)
"$BIN/scans2bag" --have-ros1 && formats+=(ros1) || echo "no ROS 1 bags in this build: ROS 2 only"
for format in "${formats[@]}"; do
  ext=""; [ "$format" = ros1 ] && ext=".bag"
  good="$WORK/good_$format$ext" noxyz="$WORK/noxyz_$format$ext" cut="$WORK/cut_$format$ext"
  "$BIN/scans2bag" "$WORK/scans" "$WORK/times.txt" "$good" "$format" --tum "$WORK/traj.tum" --pose-topic /odom
  "$BIN/scans2bag" "$WORK/scans" "$WORK/times.txt" "$noxyz" "$format" --layout no_xyz
  "$BIN/scans2bag" "$WORK/scans" "$WORK/times.txt" "$cut" "$format" --truncate 1
  "$BIN/map-build" "$WORK/ok.ini" --set MapBuild.bag="$good" > "$WORK/ok.log" || { cat "$WORK/ok.log"; fail "the good bag failed"; }
  rm -rf "$WORK/out"
  check_rejected "$format: no such topic" "$good: has no topic /velodyne (its sensor_msgs/PointCloud2 topics: /points)" \
    --set MapBuild.bag="$good" --set MapBuild.bag_lidar_topic=/velodyne
  check_rejected "$format: topic of another type" \
    "$good: topic /odom holds geometry_msgs/PoseStamped messages, not sensor_msgs/PointCloud2" \
    --set MapBuild.bag="$good" --set MapBuild.bag_lidar_topic=/odom
  check_rejected "$format: no x/y/z" "$noxyz topic /points message 0: fields lack x, y or z (fields: a b c intensity)" \
    --set MapBuild.bag="$noxyz"
  check_rejected "$format: truncated point data" "$cut topic /points message 1: truncated point data: " \
    --set MapBuild.bag="$cut"
  check_rejected "$format: pose topic of another type" "topic /points holds sensor_msgs/PointCloud2 messages, not geometry_msgs/PoseStamped" \
    --set MapBuild.bag="$good" --set MapBuild.trajectory= --set MapBuild.trajectory_format=bag \
    --set MapBuild.bag_pose_topic=/points
  check_rejected "$format: scan time without a pose" "$good topic /points message 1: its time 1317000000.2 s has no pose" \
    --set MapBuild.bag="$good" --set MapBuild.trajectory_format=bag --set MapBuild.bag_pose_topic=/odom \
    --set MapBuild.max_pose_gap_s=0.1 --set MapBuild.trajectory=
done
check_rejected "missing bag" "[MapBuild] bag: '$WORK/none.bag' does not exist" --set MapBuild.bag="$WORK/none.bag"
echo "OK"
