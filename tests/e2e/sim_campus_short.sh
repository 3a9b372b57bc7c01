# The simulated car on a one-block campus (share/quasiloc/sim/campus_car.ini, made small) for 2 s, from 2 s after the
# start (pulling away): the rig the outputs show is the KITTI-like car's (1242x375 images at 10 Hz, 100 Hz IMU with
# drawn biases, its densities in calib.ini), the motion a car's (level, camera at 1.65 m, accelerating within its
# limit), and the map is built from sweeps of the campus: windows lose returns, the map lies on the true surfaces.
source "$(dirname "$0")/common.sh"
OUT="$WORK/campus"
"$BIN/sim-rawlog" share/quasiloc/sim/campus_car.ini --set Simulation.output_dir="$OUT" --set Simulation.seed=4 \
  --set Simulation.duration_s=2 --set Simulation.start_offset_s=2 --set Simulation.inspection_png=false \
  --set World.campus_blocks_per_side=1 --set World.campus_block_size_m=40 --set World.texture_size_px=128 \
  --set World.shadow_map_px=256 --set Lidar.sweep_beams=32 --set Lidar.sweep_azimuth_steps=512 \
  --set Lidar.sweep_every=20 --set Lidar.sweep_cubemap_px=512 --set Lidar.sweep_voxel_m=0.1 | tee "$WORK/log.txt"
for f in gt.tum gt_body.tum gt_imu_bias.csv calib.ini lidar_map.map campus_car.rawlog; do
  [ -s "$OUT/$f" ] || fail "$f missing"
done
rawlog-edit --info -i "$OUT/campus_car.rawlog" > "$WORK/info.txt" 2>&1 || { cat "$WORK/info.txt"; fail "rawlog-edit cannot read it"; }
grep -Eq "stereo */ *21 */" "$WORK/info.txt" || { cat "$WORK/info.txt"; fail "not 21 stereo observations (2 s at 10 Hz)"; }
grep -Eq "imu */ *20[01] */" "$WORK/info.txt" || { cat "$WORK/info.txt"; fail "not 200-201 IMU observations (2 s at 100 Hz)"; }
expect_contains "$OUT/calib.ini" "0.0001745"  # the car IMU's gyroscope noise density (kitti_car_imu.yaml)
expect_contains "$OUT/README.txt" "outdoor campus"
/usr/bin/python3 - "$OUT" "$WORK/log.txt" <<'PY' || fail "the outputs do not show the car rig, a car's motion or a swept campus map"
import glob, re, sys
import cv2
import numpy as np
out, log = sys.argv[1], open(sys.argv[2]).read()
def fail(msg):
    print("FAIL:", msg); sys.exit(1)
left = sorted(glob.glob(f"{out}/campus_car_Images/*_left.png"))
if len(left) != 21: fail(f"{len(left)} left images, expected 21")
im = cv2.imread(left[-1], cv2.IMREAD_UNCHANGED)
if im is None or im.shape != (375, 1242): fail(f"shape {None if im is None else im.shape}, expected 375 x 1242 mono")
if im.std() < 10: fail(f"image contrast {im.std()}: nothing to see")
def tum(path):
    return np.array([[float(v) for v in l.split()] for l in open(path) if not l.startswith("#") and l.strip()])
cam, body = tum(f"{out}/gt.tum"), tum(f"{out}/gt_body.tum")
if abs(np.median(np.diff(cam[:, 0])) - 0.1) > 1e-6: fail("frame period is not 0.1 s")
if abs(np.median(np.diff(body[:, 0])) - 0.01) > 1e-6: fail("IMU period is not 0.01 s")
bias = np.loadtxt(f"{out}/gt_imu_bias.csv", delimiter=",", comments="#")
g, a = np.abs(bias[:, 1:4]), np.abs(bias[:, 4:7])
if g.min() < 0.25 * 0.005 or a.min() < 0.25 * 0.05: fail(f"a bias axis near zero: gyro {g.min()}, acc {a.min()}")
if abs(cam[:, 3].mean() - 1.65) > 0.05: fail(f"camera height {cam[:, 3].mean()} m, expected 1.65")
v = np.linalg.norm(np.diff(cam[:, 1:3], axis=0), axis=1) / 0.1
if v[-1] < 1.0 or v.max() > 10.01: fail(f"speeds {v.min()}..{v.max()} m/s: not a car pulling away")
if np.max(np.abs(np.diff(v))) / 0.1 > 1.6: fail("acceleration beyond car_max_accel_m_s2")
m = re.search(r"(\d+) lost on glass", log)
if not m or int(m.group(1)) == 0: fail("no LiDAR return lost on the windows")
m = re.search(r"map-build: (\d+) points", log)
if not m or int(m.group(1)) < 20000: fail(f"swept map too small: {m and m.group(1)}")
points = int(m.group(1))
m = re.search(r"true surfaces median ([\d.]+) mm", log)
if not m or float(m.group(1)) > 30: fail(f"the map lies {m and m.group(1)} mm (median) from the campus's surfaces")
print(f"campus ok: {len(left)} frames, speed up to {v.max():.2f} m/s, map {points} points")
PY
