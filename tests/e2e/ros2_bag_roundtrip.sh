# A simulated sequence through a ROS 2 bag and back: sim rawlog -> rawlog2bag format=mcap (a rosbag2 folder) ->
# bag2rawlog gives the same observations (images pixel for pixel, IMU values exact: exporting both rawlogs again gives
# byte-identical MCAP files), with the calibration from the Kalibr files and, without them, from the bag's CameraInfo
# and /tf_static (the same numbers to 1e-9). Each chunk compression (zstd, lz4, none), a bare .mcap path, png and mono16
# images convert to the same images.
# A real rosbag2 recording (Crystal, SQLite3: a bgr8 Image, a jpeg CompressedImage, an Imu) converts. Bad input
# (a truncated file, a chunk whose CRC fails, an unknown storage, an unknown compression, a missing topic, a topic of
# a type bag2rawlog does not read) is an error naming the file and the topic, exits non-zero and leaves nothing.
source "$(dirname "$0")/common.sh"
source "$(dirname "$0")/ros2_bag_common.sh"
ROS2="$SHARED/data/ros2"
SIM="$WORK/sim"
"$BIN/sim-rawlog" config.ini --set Simulation.output_dir="$SIM" --set Simulation.duration_s=2 \
  --set Simulation.inspection_png=false "${EXACT_MAP[@]}" > "$WORK/sim.txt"
to_bag() {  # to_bag <rawlog> <calib.ini> <bag folder> [--set ...]
  local rawlog="$1" calib="$2" bag="$3"; shift 3
  "$BIN/rawlog2bag" config.ini --set Rawlog2Bag.input_rawlog="$rawlog" --set Rawlog2Bag.calibration_ini="$calib" \
    --set Rawlog2Bag.output_bag="$bag" --set Rawlog2Bag.format=mcap --set Rawlog2Bag.progress=false "$@" \
    > "$bag.log" 2>&1 || { cat "$bag.log"; fail "rawlog2bag failed on $rawlog"; }
}
to_rawlog() {  # to_rawlog <bag> <rawlog> [--set ...]
  local bag="$1" out="$2"; shift 2
  mkdir -p "$(dirname "$out")"
  "$BIN/bag2rawlog" config.ini --set Bag2Rawlog.input_bag="$bag" --set Bag2Rawlog.output="$out" \
    --set Bag2Rawlog.progress=false "$@" > "$out.log" 2>&1 || { cat "$out.log"; fail "bag2rawlog failed on $bag"; }
  cat "$out.log"
}
kalibr() { echo --set Bag2Rawlog.kalibr_camchain="$1_camchain.yaml" --set Bag2Rawlog.kalibr_imu="$1_imu.yaml"; }
same_calibration() {  # same_calibration <ini A> <ini B>: every number within 1e-9
  /usr/bin/python3 - "$1" "$2" <<'PY' || fail "calibrations differ: $1 $2"
import re, sys
def values(p):
    out = {}
    section = ""
    for line in open(p):
        line = line.strip()
        if not line or line.startswith("#"): continue
        if line.startswith("["): section = line; continue
        k, v = line.split("=", 1)
        out[section + k.strip()] = [float(x) if re.match(r"^[-+0-9.eE]+$", x) else x for x in v.strip(" []").split()]
    return out
a, b = values(sys.argv[1]), values(sys.argv[2])
assert a.keys() == b.keys(), set(a) ^ set(b)
for k in a:
    for x, y in zip(a[k], b[k]):
        assert (abs(x - y) < 1e-9) if isinstance(x, float) else x == y, (k, x, y)
print(len(a), "calibration values equal")
PY
}
nothing_in() { [ -z "$(ls -A "$1" 2>/dev/null)" ] || fail "output left behind in $1: $(ls -A "$1")"; }

# 1. The round trip (zstd chunks, the default compression for MCAP here), with the ground truth.
to_bag "$SIM/V1_01_easy.rawlog" "$SIM/calib.ini" "$WORK/sim_mcap" --set Rawlog2Bag.compression=zstd \
  --set Rawlog2Bag.groundtruth="$SIM/gt.tum"
cat "$WORK/sim_mcap.log"
for f in sim_mcap/metadata.yaml sim_mcap/sim_mcap_0.mcap sim_mcap_camchain.yaml sim_mcap_imu.yaml; do
  [ -s "$WORK/$f" ] || fail "$f missing"
done
expect_contains "$WORK/sim_mcap/metadata.yaml" "storage_identifier: mcap"
expect_contains "$WORK/sim_mcap/metadata.yaml" "type: sensor_msgs/msg/CameraInfo"
to_rawlog "$WORK/sim_mcap" "$WORK/rt/seq.rawlog" $(kalibr "$WORK/sim_mcap") --set Bag2Rawlog.groundtruth_topic=/groundtruth
expect_contains "$WORK/rt/seq.rawlog.log" "rosbag2 mcap"
expect_contains "$WORK/rt/seq.rawlog.log" "unpaired images:       0 left, 0 right"
same_images "$SIM/V1_01_easy_Images" "$WORK/rt/seq_Images"
diff <(grep -v '^#' "$SIM/calib.ini") <(grep -v '^#' "$WORK/rt/seq_calib.ini") || fail "the calibration changed"
same_groundtruth "$SIM/gt.tum" "$WORK/rt/seq_gt_cam0.tum"
# Every observation: both rawlogs exported again give the same MCAP file, byte for byte.
to_bag "$SIM/V1_01_easy.rawlog" "$SIM/calib.ini" "$WORK/a" --set Rawlog2Bag.compression=zstd
to_bag "$WORK/rt/seq.rawlog" "$WORK/rt/seq_calib.ini" "$WORK/b" --set Rawlog2Bag.compression=zstd
cmp "$WORK/a/a_0.mcap" "$WORK/b/b_0.mcap" || fail "the round-tripped rawlog exports to another MCAP file"

# 2. The calibration from the bag itself: CameraInfo, /tf_static, the IMU noise model from an INI's [imu] section.
to_rawlog "$WORK/sim_mcap" "$WORK/fromtf/seq.rawlog" --set Bag2Rawlog.imu_ini="$SIM/calib.ini"
same_images "$SIM/V1_01_easy_Images" "$WORK/fromtf/seq_Images"
same_calibration "$SIM/calib.ini" "$WORK/fromtf/seq_calib.ini"
expect_contains "$WORK/fromtf/seq_calib.ini" "/cam0/camera_info"

# 3. lz4 and uncompressed chunks, and a bare .mcap path (no metadata.yaml); png CompressedImage and mono16 messages.
for c in lz4 none; do
  to_bag "$SIM/V1_01_easy.rawlog" "$SIM/calib.ini" "$WORK/$c" --set Rawlog2Bag.compression=$c
  to_rawlog "$WORK/$c/${c}_0.mcap" "$WORK/$c.out/seq.rawlog" $(kalibr "$WORK/$c")
  same_images "$SIM/V1_01_easy_Images" "$WORK/$c.out/seq_Images"
done
for enc in png mono16; do
  to_bag "$SIM/V1_01_easy.rawlog" "$SIM/calib.ini" "$WORK/$enc" --set Rawlog2Bag.image_encoding=$enc
  to_rawlog "$WORK/$enc" "$WORK/$enc.out/seq.rawlog" $(kalibr "$WORK/$enc")
  same_images "$SIM/V1_01_easy_Images" "$WORK/$enc.out/seq_Images"
done
expect_contains "$WORK/png.out/seq.rawlog.log" "(sensor_msgs/CompressedImage)"

# 4. A real rosbag2 recording (Crystal era, legacy SQLite3 schema, no metadata.yaml): its bgr8 Image and jpeg
# CompressedImage (recorded days apart: paired only with a huge tolerance) and its Imu become one stereo frame.
sample="$ROS2/rosbag2js_sensor_sample_sqlite3/sample.db3"
if [ -f "$sample" ]; then
  /usr/bin/python3 - "$WORK/sample" <<'PY'
import sys
cam = lambda name: f"""{name}:
  camera_model: pinhole
  intrinsics: [500, 500, 320, 240]
  resolution: [640, 480]
  distortion_model: radtan
  distortion_coeffs: [0, 0, 0, 0]
  T_cam_imu: [[1, 0, 0, 0], [0, 1, 0, {0.05 if name == 'cam1' else 0}], [0, 0, 1, 0], [0, 0, 0, 1]]
"""
open(sys.argv[1] + "_camchain.yaml", "w").write(cam("cam0") + cam("cam1"))
open(sys.argv[1] + "_imu.yaml", "w").write("update_rate: 200\naccelerometer_noise_density: 0.01\n"
    "accelerometer_random_walk: 0.001\ngyroscope_noise_density: 0.001\ngyroscope_random_walk: 0.0001\n")
PY
  to_rawlog "$sample" "$WORK/sample.out/seq.rawlog" $(kalibr "$WORK/sample") --set Bag2Rawlog.left_topic=/image \
    --set Bag2Rawlog.right_topic=/image/compressed --set Bag2Rawlog.imu_topic=/imu \
    --set Bag2Rawlog.pair_tolerance_ms=1e9 --set Bag2Rawlog.reorder_window_s=1e9
  expect_contains "$WORK/sample.out/seq.rawlog.log" "stereo frames written: 1"
  expect_contains "$WORK/sample.out/seq.rawlog.log" "IMU samples written:   1"
fi

# 5. Bad input: each an error naming the file (and the topic where there is one), nothing written.
bad() {  # bad <name> <bag> <expected text> [--set ...]: bag2rawlog fails naming it, leaves nothing
  local name="$1" bag="$2" text="$3"; shift 3
  expect_failure "$WORK/$name.txt" "$BIN/bag2rawlog" config.ini --set Bag2Rawlog.input_bag="$bag" \
    --set Bag2Rawlog.output="$WORK/bad_$name/seq.rawlog" --set Bag2Rawlog.progress=false "$@"
  expect_contains "$WORK/$name.txt" "$text"
  nothing_in "$WORK/bad_$name"
  echo "$name: $(grep -m1 -i error "$WORK/$name.txt" || tail -n 1 "$WORK/$name.txt")"
}
cp -r "$WORK/none" "$WORK/cut"; mv "$WORK/cut/none_0.mcap" "$WORK/cut/cut_0.mcap"
sed -i 's/none_0.mcap/cut_0.mcap/' "$WORK/cut/metadata.yaml"
truncate -s $(( $(stat -c %s "$WORK/cut/cut_0.mcap") / 2 )) "$WORK/cut/cut_0.mcap"
bad truncated "$WORK/cut" "cut/cut_0.mcap" $(kalibr "$WORK/none")
cp -r "$WORK/none" "$WORK/crc"
/usr/bin/python3 - "$WORK/crc/none_0.mcap" <<'PY'
import sys
p = sys.argv[1]; b = bytearray(open(p, "rb").read())
b[len(b) // 3] ^= 0x5A  # inside an image of an uncompressed chunk
open(p, "wb").write(bytes(b))
PY
bad chunk_crc "$WORK/crc" "chunk CRC mismatch" $(kalibr "$WORK/none")
expect_contains "$WORK/chunk_crc.txt" "crc/none_0.mcap"
cp -r "$WORK/none" "$WORK/storage"; sed -i 's/storage_identifier: mcap/storage_identifier: leveldb/' "$WORK/storage/metadata.yaml"
bad storage "$WORK/storage" "storage_identifier 'leveldb' is not supported" $(kalibr "$WORK/none")
expect_contains "$WORK/storage.txt" "storage/metadata.yaml"
cp -r "$WORK/none" "$WORK/compr"
sed -i 's/compression_format: ""/compression_format: "lz4"/; s/compression_mode: ""/compression_mode: "MESSAGE"/' \
  "$WORK/compr/metadata.yaml"
bad compression "$WORK/compr" "compression_format 'lz4' is not supported" $(kalibr "$WORK/none")
bad missing_topic "$WORK/none" "topic /imu_missing" $(kalibr "$WORK/none") --set Bag2Rawlog.imu_topic=/imu_missing
expect_contains "$WORK/missing_topic.txt" "$WORK/none"
bad unknown_type "$ROS2/rosbag2_talker_mcap" "topic /topic ([Bag2Rawlog] left_topic): holds std_msgs/String" \
  $(kalibr "$WORK/none") --set Bag2Rawlog.left_topic=/topic
expect_contains "$WORK/unknown_type.txt" "rosbag2_talker_mcap"
echo "OK"
