# map-build from a bag gives the map map-build makes from the same scans as files, point for point: 8 real KITTI
# scans (frames 0, 10, ..., 70 of ../shared/data/kitti_raw_seq78) written by scans2bag as sensor_msgs/PointCloud2
# into a ROS 1 bag (x y z intensity float32; where this build has ROS 1 bags) and a ROS 2 MCAP bag (float64, an
# organised cloud with NaN points and padded rows, big-endian), stamped like the scans' times file, with the
# trajectory as a TUM file and as a PoseStamped topic of the bag. Every map must equal the files' map byte for byte.
# The bags also carry /tf_static (base_link -> cam2, base_link -> imu_link -> velodyne: calib.txt's T_cam2rect_velo
# split over three links): map-build with extrinsic_source = tf_static must chain it to calib.txt's extrinsic (to
# 1e-6: the links hold quaternions) and give, byte for byte, the map of the files built with the T_body_lidar it
# printed given as keys.
source "$(dirname "$0")/common.sh"
DATA="$SHARED/data/kitti_raw_seq78"
mkdir -p "$WORK/scans"
FRAMES="0 10 20 30 40 50 60 70"
for f in $FRAMES; do ln -s "$DATA/velodyne_even/$(printf %010d $f).bin" "$WORK/scans/"; done
# Frame f at T0 + f / 10 s; the TUM trajectory T_world_cam2 of every frame (the extrinsic stays calib.txt's).
/usr/bin/python3 - "$DATA/poses_cam2.txt" "$WORK" $FRAMES <<'PY'
import sys
import numpy as np
sys.path.insert(0, "scripts")
import kitti_map_check as k
poses, work, frames = k.load_poses(sys.argv[1]), sys.argv[2], [int(f) for f in sys.argv[3:]]
stamp = lambda f: "1317000000.%09d" % (f * 100000000) if f < 10 else "%d.%09d" % (1317000000 + f // 10, (f % 10) * 100000000)
with open(work + "/times.txt", "w") as out:
    for f in frames:
        out.write(stamp(f) + "\n")
def quaternion(R):  # x y z w, from a rotation matrix (w > 0)
    w = np.sqrt(max(0.0, 1 + R[0, 0] + R[1, 1] + R[2, 2])) / 2
    x = np.copysign(np.sqrt(max(0.0, 1 + R[0, 0] - R[1, 1] - R[2, 2])) / 2, R[2, 1] - R[1, 2])
    y = np.copysign(np.sqrt(max(0.0, 1 - R[0, 0] + R[1, 1] - R[2, 2])) / 2, R[0, 2] - R[2, 0])
    z = np.copysign(np.sqrt(max(0.0, 1 - R[0, 0] - R[1, 1] + R[2, 2])) / 2, R[1, 0] - R[0, 1])
    q = np.array([x, y, z, w])
    return q / np.linalg.norm(q)
with open(work + "/traj.tum", "w") as out:
    for f, T in enumerate(poses):
        q = quaternion(T[:3, :3])
        out.write("%s %.9f %.9f %.9f %.12f %.12f %.12f %.12f\n" % ((stamp(f),) + tuple(T[:3, 3]) + tuple(q)))
# /tf_static: T_cam2_velo (calib.txt, rotation made orthonormal) = T_base_cam2^-1 * T_base_imu * T_imu_velo.
calib = {l.split(":")[0]: l.split(":")[1].split() for l in open(sys.argv[1].replace("poses_cam2.txt", "calib.txt")) if ":" in l}
T_cam2_velo = np.eye(4)
T_cam2_velo[:3, :] = np.array([float(v) for v in calib["T_cam2rect_velo"]]).reshape(3, 4)
u, _, vt = np.linalg.svd(T_cam2_velo[:3, :3])
T_cam2_velo[:3, :3] = u @ vt
def transform(t, axis, angle):
    a = np.array(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    T = np.eye(4)
    T[:3, :3] = np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K
    T[:3, 3] = t
    return T
T_base_cam2 = transform([1.2, 0.3, 1.5], [1, -2, 0.5], 1.9)
T_base_imu = transform([0.1, 0.05, 1.0], [0, 0, 1], 0.7)
T_imu_velo = np.linalg.inv(T_base_imu) @ T_base_cam2 @ T_cam2_velo
with open(work + "/tf.txt", "w") as out:
    for parent, child, T in (("base_link", "cam2", T_base_cam2), ("base_link", "imu_link", T_base_imu), ("imu_link", "velodyne", T_imu_velo)):
        out.write("%s %s %s\n" % (parent, child, " ".join("%.17g" % v for v in tuple(T[:3, 3]) + tuple(quaternion(T[:3, :3])))))
with open(work + "/T_cam2_velo.txt", "w") as out:
    out.write(" ".join("%.17g" % v for v in T_cam2_velo[:3, :].ravel()) + "\n")
PY
tf_args=()
while read -r link; do tf_args+=(--tf "$link"); done < "$WORK/tf.txt"
run_build() {  # run_build <name> [--set ...]
  local name="$1"; shift
  "$BIN/map-build" rawlog_tools/map-build/kitti_raw_seq78.ini --set MapBuild.scan_folder="$WORK/scans" \
    --set MapBuild.trajectory="$WORK/traj.tum" --set MapBuild.trajectory_format=tum \
    --set MapBuild.extrinsic_file="$DATA/calib.txt" --set MapBuild.output="$WORK/$name.map" "$@" > "$WORK/$name.log" \
    || { cat "$WORK/$name.log"; fail "map-build $name failed"; }
  grep -E "^(scans|points|wrote|extrinsic) " "$WORK/$name.log" | sed "s|^|$name: |"
}
same_map() {  # same_map <name>: the map equals the files' map byte for byte
  cmp "$WORK/files.map" "$WORK/$1.map" || fail "the map from $1 differs from the map from the files"
  echo "$1: identical to the files' map ($(stat -c %s "$WORK/$1.map") bytes)"
}
run_build files --set MapBuild.scan_times=file --set MapBuild.scan_times_file="$WORK/times.txt"
formats=(mcap)
"$BIN/scans2bag" --have-ros1 && formats+=(ros1) || echo "no ROS 1 bags in this build: ROS 2 only"
for format in "${formats[@]}"; do
  if [ "$format" = ros1 ]; then bag="$WORK/run.bag"; layout=(--layout xyzi32); else bag="$WORK/run_mcap"; layout=(--layout organised64 --big-endian); fi
  "$BIN/scans2bag" "$WORK/scans" "$WORK/times.txt" "$bag" "$format" --topic /velodyne_points "${layout[@]}" \
    --tum "$WORK/traj.tum" --pose-topic /odom "${tf_args[@]}"
  run_build "bag_$format" --set MapBuild.source=bag --set MapBuild.bag="$bag" --set MapBuild.scan_times=auto
  expect_contains "$WORK/bag_$format.log" "scans       8 PointCloud2 messages of /velodyne_points in $bag"
  same_map "bag_$format"
  # The trajectory from the bag's own pose topic.
  run_build "bag_poses_$format" --set MapBuild.source=bag --set MapBuild.bag="$bag" --set MapBuild.scan_times=auto \
    --set MapBuild.trajectory= --set MapBuild.trajectory_format=bag --set MapBuild.bag_pose_topic=/odom
  expect_contains "$WORK/bag_poses_$format.log" "poses from $bag topic /odom (78 poses)"
  same_map "bag_poses_$format"
  # The extrinsic from the bag's /tf_static, chained cam2 <- base_link -> imu_link -> velodyne.
  run_build "bag_tf_$format" --set MapBuild.source=bag --set MapBuild.bag="$bag" --set MapBuild.scan_times=auto \
    --set MapBuild.extrinsic_file= --set MapBuild.extrinsic_source=tf_static --set MapBuild.body_frame=cam2
  expect_contains "$WORK/bag_tf_$format.log" "extrinsic   from $bag topic /tf_static: cam2 <- base_link -> imu_link -> velodyne"
  T=$(sed -n 's/^ *T_body_lidar = //p' "$WORK/bag_tf_$format.log")
  /usr/bin/python3 - "$T" "$(cat "$WORK/T_cam2_velo.txt")" <<'PY' || fail "the extrinsic from /tf_static is not calib.txt's"
import sys
got, want = [float(v) for v in sys.argv[1].split()], [float(v) for v in sys.argv[2].split()]
err = max(abs(a - b) for a, b in zip(got, want)) if len(got) == 12 else float("inf")
print("T_body_lidar from /tf_static: largest difference to calib.txt's %.3g" % err)
sys.exit(0 if err < 1e-6 else 1)
PY
  run_build "files_tf_keys_$format" --set MapBuild.scan_times=file --set MapBuild.scan_times_file="$WORK/times.txt" \
    --set MapBuild.extrinsic_file= --set "MapBuild.T_body_lidar=$T"
  cmp "$WORK/files_tf_keys_$format.map" "$WORK/bag_tf_$format.map" \
    || fail "the map with the extrinsic from /tf_static differs from the map with it given as keys"
  echo "bag_tf_$format: identical to the files' map with T_body_lidar as keys ($(stat -c %s "$WORK/bag_tf_$format.map") bytes)"
done
expect_contains "$WORK/bag_mcap.log" "without a position dropped"
echo "OK"
