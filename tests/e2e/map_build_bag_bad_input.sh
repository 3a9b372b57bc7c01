# map-build's bad bag inputs: a bag without the topic, a topic of another type, a PointCloud2 without x/y/z, a
# truncated point buffer, a pose topic of another type, a missing bag; with extrinsic_source = tf_static: no
# /tf_static, a LiDAR frame in no transform, body and LiDAR frames not connected, a cycle, scans of two frame_ids,
# and the keys that contradict it. Each is an error naming the bag, the topic and (for a message) its index or (for
# /tf_static) the frames, a non-zero exit, and nothing written. In a ROS 2 MCAP bag, and in a ROS 1 bag where this
# build has them.
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
  link="0.1 0 0.2 0 0 0 1"
  notf="$WORK/notf_$format$ext" cycle="$WORK/cycle_$format$ext" apart="$WORK/apart_$format$ext" mixed="$WORK/mixed_$format$ext"
  "$BIN/scans2bag" "$WORK/scans" "$WORK/times.txt" "$notf" "$format" --tf "base_link imu_link $link"
  "$BIN/scans2bag" "$WORK/scans" "$WORK/times.txt" "$apart" "$format" --tf "base_link imu_link $link" \
    --tf "odom velodyne $link"
  "$BIN/scans2bag" "$WORK/scans" "$WORK/times.txt" "$cycle" "$format" --tf "base_link imu_link $link" \
    --tf "imu_link base_link $link" --tf "imu_link velodyne $link"
  "$BIN/scans2bag" "$WORK/scans" "$WORK/times.txt" "$mixed" "$format" --other-frame 1 os_sensor \
    --tf "base_link velodyne $link"
  "$BIN/map-build" "$WORK/ok.ini" --set MapBuild.bag="$good" > "$WORK/ok.log" || { cat "$WORK/ok.log"; fail "the good bag failed"; }
  rm -rf "$WORK/out"
  tf=(--set MapBuild.extrinsic_file= --set MapBuild.extrinsic_source=tf_static --set MapBuild.body_frame=base_link)
  frames="(T_body_lidar from body_frame 'base_link' to the LiDAR frame 'velodyne', the header.frame_id of /points)"
  check_rejected "$format: no /tf_static" \
    "$good: has no topic /tf_static (its tf2_msgs/TFMessage topics: none) $frames" --set MapBuild.bag="$good" "${tf[@]}"
  check_rejected "$format: LiDAR frame in no transform" "$notf topic /tf_static: frame 'velodyne' is in no static \
transform (transforms there, parent -> child: base_link -> imu_link) $frames" --set MapBuild.bag="$notf" "${tf[@]}"
  check_rejected "$format: frames not connected" "$apart topic /tf_static: no chain of static transforms from \
'base_link' to 'velodyne' (transforms there, parent -> child: base_link -> imu_link, odom -> velodyne) $frames" \
    --set MapBuild.bag="$apart" "${tf[@]}"
  check_rejected "$format: a cycle" "$cycle topic /tf_static: the parents of frame 'base_link' lead back to a frame \
passed before: a cycle (transforms there, parent -> child: base_link -> imu_link, imu_link -> base_link, imu_link -> \
velodyne) $frames" --set MapBuild.bag="$cycle" "${tf[@]}"
  check_rejected "$format: scans of two frames" "$mixed topic /points message 1: has header.frame_id 'os_sensor' where \
message 0 has 'velodyne': the scans of one topic must share one LiDAR frame" --set MapBuild.bag="$mixed" "${tf[@]}"
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
check_rejected "tf_static and extrinsic_file" "[MapBuild] extrinsic_source: tf_static: give the extrinsic once" \
  --set MapBuild.bag="$WORK/good_mcap" --set MapBuild.extrinsic_source=tf_static --set MapBuild.body_frame=base_link
check_rejected "tf_static without body_frame" "[MapBuild] body_frame: is required with extrinsic_source = tf_static" \
  --set MapBuild.bag="$WORK/good_mcap" --set MapBuild.extrinsic_file= --set MapBuild.extrinsic_source=tf_static
check_rejected "tf_static with scan files" "[MapBuild] extrinsic_source: tf_static needs the scans from a bag" \
  --set MapBuild.source=folder --set MapBuild.scan_folder="$WORK/scans" --set MapBuild.extrinsic_file= \
  --set MapBuild.extrinsic_source=tf_static --set MapBuild.body_frame=base_link
check_rejected "missing bag" "[MapBuild] bag: '$WORK/none.bag' does not exist" --set MapBuild.bag="$WORK/none.bag"
echo "OK"
