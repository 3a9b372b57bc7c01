# The simulated ground robot (share/quasiloc/sim/robot_floor.ini) for 3 s, started moving: the rig the outputs show is
# the D435i's (848x480 images, 30 Hz frames, 200 Hz IMU, the BMI055's densities in calib.ini), the IMU's true biases
# are not zero, and the motion is a ground robot's (level, z within a few mm, at most 1.5 m/s, moving at the start).
source "$(dirname "$0")/common.sh"
OUT="$WORK/robot"
"$BIN/sim-rawlog" share/quasiloc/sim/robot_floor.ini --set Simulation.output_dir="$OUT" --set Simulation.seed=5 \
  --set Simulation.duration_s=3 --set Simulation.robot_start_moving=true --set Simulation.write_map=false \
  --set Simulation.inspection_png=false | tee "$WORK/log.txt"
for f in gt.tum gt_body.tum gt_imu_bias.csv calib.ini robot_floor.rawlog; do [ -s "$OUT/$f" ] || fail "$f missing"; done
rawlog-edit --info -i "$OUT/robot_floor.rawlog" > "$WORK/info.txt" 2>&1 || { cat "$WORK/info.txt"; fail "rawlog-edit cannot read it"; }
grep -Eq "stereo */ *91 */" "$WORK/info.txt" || { cat "$WORK/info.txt"; fail "not 91 stereo observations (3 s at 30 Hz)"; }
grep -Eq "imu */ *60[01] */" "$WORK/info.txt" || { cat "$WORK/info.txt"; fail "not 600-601 IMU observations (3 s at 200 Hz)"; }
expect_contains "$OUT/calib.ini" "0.0002443"   # the BMI055's gyroscope noise density (d435i_imu.yaml)
expect_contains "$OUT/calib.ini" "0.001471"    # and its accelerometer's
/usr/bin/python3 - "$OUT" <<'PY' || fail "the outputs do not show the D435i rig or a ground robot's motion"
import glob, sys
import cv2
import numpy as np
out = sys.argv[1]
def fail(msg):
    print("FAIL:", msg); sys.exit(1)
left = sorted(glob.glob(f"{out}/robot_floor_Images/*_left.png"))
right = sorted(glob.glob(f"{out}/robot_floor_Images/*_right.png"))
if len(left) != 91 or len(right) != 91: fail(f"{len(left)} left / {len(right)} right images, expected 91")
for f in (left[0], right[-1]):
    im = cv2.imread(f, cv2.IMREAD_UNCHANGED)
    if im is None or im.shape != (480, 848): fail(f"{f}: shape {None if im is None else im.shape}, expected 480 x 848 mono")
def tum(path):
    return np.array([[float(v) for v in l.split()] for l in open(path) if not l.startswith("#") and l.strip()])
cam, body = tum(f"{out}/gt.tum"), tum(f"{out}/gt_body.tum")
dt_cam, dt_imu = np.median(np.diff(cam[:, 0])), np.median(np.diff(body[:, 0]))
if abs(dt_cam - 1 / 30) > 1e-6: fail(f"frame period {dt_cam} s, expected 1/30")
if abs(dt_imu - 1 / 200) > 1e-6: fail(f"IMU period {dt_imu} s, expected 1/200")
bias = np.loadtxt(f"{out}/gt_imu_bias.csv", delimiter=",", comments="#")
g, a = np.abs(bias[:, 1:4]), np.abs(bias[:, 4:7])
if g.min() < 0.25 * 0.00873 or a.min() < 0.25 * 0.08: fail(f"a bias axis near zero: gyro {g.min()}, acc {a.min()}")
if g.max() > 1.5 * 0.00873 or a.max() > 1.5 * 0.08: fail(f"a bias beyond the drawn bound: gyro {g.max()}, acc {a.max()}")
# Planar: the camera's height varies by millimetres, its optical y axis (down) stays within a degree of gravity.
z = cam[:, 3]
if z.max() - z.min() > 0.01: fail(f"camera height varies by {z.max() - z.min()} m")
def down_tilt_deg(q):
    x, y, zq, w = q
    R = np.array([[1 - 2 * (y * y + zq * zq), 2 * (x * y - zq * w), 2 * (x * zq + y * w)],
                  [2 * (x * y + zq * w), 1 - 2 * (x * x + zq * zq), 2 * (y * zq - x * w)],
                  [2 * (x * zq - y * w), 2 * (y * zq + x * w), 1 - 2 * (x * x + y * y)]])
    return np.degrees(np.arccos(np.clip(-R[2, 1], -1, 1)))
tilt = max(down_tilt_deg(q) for q in cam[:, 4:8])
if tilt > 1.0: fail(f"camera tilted {tilt} deg from level")
speed = np.linalg.norm(np.diff(body[:, 1:3], axis=0), axis=1) / np.diff(body[:, 0])
if speed.max() > 1.55: fail(f"speed {speed.max()} m/s above 1.5")
if speed[:20].mean() < 0.3: fail(f"not moving at the start: {speed[:20].mean()} m/s")
print(f"rig and motion OK: frame period {dt_cam:.6f} s, IMU {dt_imu:.6f} s, z span {1000 * (z.max() - z.min()):.2f} mm, "
      f"tilt <= {tilt:.2f} deg, speed <= {speed.max():.2f} m/s, gyro bias >= {g.min():.4f} rad/s, acc >= {a.min():.3f}")
PY
echo "OK"
