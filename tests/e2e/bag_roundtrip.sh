# A simulated sequence through a ROS 1 bag and back: sim rawlog -> rawlog2bag (+ Kalibr YAML) -> bag2rawlog gives the
# same observations (images pixel for pixel, IMU values exact, timestamps to the nanosecond: exporting both rawlogs
# again gives byte-identical bags) and quasiloc-track gives the same trajectory on both. Then png-compressed and
# mono16 images round-trip exactly, jpeg converts; right images 3 ms late pair within a 5 ms tolerance. No pair within
# the tolerance, a missing topic and a truncated bag are errors that name the topics or the file, exit non-zero and
# leave nothing written.
source "$(dirname "$0")/common.sh"
source "$(dirname "$0")/ros2_bag_common.sh"
SIM="$WORK/sim"
"$BIN/sim-rawlog" config.ini --set Simulation.output_dir="$SIM" --set Simulation.duration_s=3 \
  --set Simulation.inspection_png=false "${EXACT_MAP[@]}" > "$WORK/sim.txt"
to_bag() {  # to_bag <rawlog> <calib.ini> <bag> [--set ...]
  local rawlog="$1" calib="$2" bag="$3"; shift 3
  "$BIN/rawlog2bag" config.ini --set Rawlog2Bag.input_rawlog="$rawlog" --set Rawlog2Bag.calibration_ini="$calib" \
    --set Rawlog2Bag.output_bag="$bag" --set Rawlog2Bag.progress=false "$@" > "$bag.log" 2>&1 \
    || { cat "$bag.log"; fail "rawlog2bag failed on $rawlog"; }
}
to_rawlog() {  # to_rawlog <bag> <rawlog> [--set ...]: the Kalibr files beside the bag are the calibration
  local bag="$1" out="$2"; shift 2
  mkdir -p "$(dirname "$out")"
  "$BIN/bag2rawlog" config.ini --set Bag2Rawlog.input_bag="$bag" --set Bag2Rawlog.output="$out" \
    --set Bag2Rawlog.kalibr_camchain="${bag%.bag}_camchain.yaml" --set Bag2Rawlog.kalibr_imu="${bag%.bag}_imu.yaml" \
    --set Bag2Rawlog.progress=false "$@" > "$out.log" 2>&1 || { cat "$out.log"; fail "bag2rawlog failed on $bag"; }
  cat "$out.log"
}

# 1. The round trip, with the ground truth.
to_bag "$SIM/V1_01_easy.rawlog" "$SIM/calib.ini" "$WORK/sim.bag" --set Rawlog2Bag.groundtruth="$SIM/gt.tum"
cat "$WORK/sim.bag.log"
for f in sim.bag sim_camchain.yaml sim_imu.yaml sim_rawlog2bag.ini; do [ -s "$WORK/$f" ] || fail "$f missing"; done
to_rawlog "$WORK/sim.bag" "$WORK/rt/seq.rawlog" --set Bag2Rawlog.groundtruth_topic=/groundtruth
for f in seq.rawlog seq_calib.ini seq_gt_cam0.tum seq_bag2rawlog.ini; do [ -s "$WORK/rt/$f" ] || fail "$f missing"; done
expect_contains "$WORK/rt/seq.rawlog.log" "unpaired images:       0 left, 0 right"
same_images "$SIM/V1_01_easy_Images" "$WORK/rt/seq_Images"
diff <(grep -v '^#' "$SIM/calib.ini") <(grep -v '^#' "$WORK/rt/seq_calib.ini") \
  || fail "the calibration changed through the Kalibr files"  # the header comments name the sources
# Every observation: both rawlogs exported again (without ground truth) give the same bag, byte for byte.
to_bag "$SIM/V1_01_easy.rawlog" "$SIM/calib.ini" "$WORK/a.bag"
to_bag "$WORK/rt/seq.rawlog" "$WORK/rt/seq_calib.ini" "$WORK/b.bag"
cmp "$WORK/a.bag" "$WORK/b.bag" || fail "the round-tripped rawlog exports to another bag"
# The ground truth comes back as T_world_cam0 within 1e-9 m.
same_groundtruth "$SIM/gt.tum" "$WORK/rt/seq_gt_cam0.tum"

# 2. quasiloc-track on both gives the same trajectory.
track() {  # track <rawlog> <calib> <gt> <out>
  "$BIN/quasiloc-track" config.ini --set Tracking.input_rawlog="$1" --set Tracking.calibration_ini="$2" \
    --set Tracking.map_file="$SIM/lidar_map.map" --set Tracking.groundtruth="$3" --set Tracking.output_dir="$4" \
    --set Initialization.init=global > "$4.log" 2>&1 || { cat "$4.log"; fail "quasiloc-track failed on $1"; }
}
track "$SIM/V1_01_easy.rawlog" "$SIM/calib.ini" "$SIM/gt.tum" "$WORK/track_sim"
track "$WORK/rt/seq.rawlog" "$WORK/rt/seq_calib.ini" "$WORK/rt/seq_gt_cam0.tum" "$WORK/track_rt"
cmp "$WORK/track_sim/trajectory.tum" "$WORK/track_rt/trajectory.tum" \
  || fail "quasiloc-track gives another trajectory on the round-tripped sequence"
echo "trajectories identical: $(grep -vc '^#' "$WORK/track_rt/trajectory.tum") poses"

# 3. Other image encodings: png (compressed) and mono16 exactly, jpeg close.
for enc in png mono16 jpeg; do
  to_bag "$SIM/V1_01_easy.rawlog" "$SIM/calib.ini" "$WORK/$enc.bag" --set Rawlog2Bag.image_encoding=$enc
  to_rawlog "$WORK/$enc.bag" "$WORK/$enc/seq.rawlog"
  [ $enc = jpeg ] || same_images "$SIM/V1_01_easy_Images" "$WORK/$enc/seq_Images"
done
expect_contains "$WORK/png/seq.rawlog.log" "(sensor_msgs/CompressedImage)"

# 4. Right images 3 ms late: paired with a 5 ms tolerance (every frame, at the left image's time); with the default
# 2 ms none pairs, an error naming both topics and the key.
to_bag "$SIM/V1_01_easy.rawlog" "$SIM/calib.ini" "$WORK/late.bag" --set Rawlog2Bag.right_delay_ms=3
to_rawlog "$WORK/late.bag" "$WORK/late/seq.rawlog" --set Bag2Rawlog.pair_tolerance_ms=5
expect_contains "$WORK/late/seq.rawlog.log" "stereo frames written: 61 (largest left-right offset 3.000 ms)"
same_images "$SIM/V1_01_easy_Images" "$WORK/late/seq_Images"
expect_failure "$WORK/late2.txt" "$BIN/bag2rawlog" config.ini --set Bag2Rawlog.input_bag="$WORK/late.bag" \
  --set Bag2Rawlog.output="$WORK/bad0/seq.rawlog" \
  --set Bag2Rawlog.kalibr_camchain="$WORK/late_camchain.yaml" --set Bag2Rawlog.kalibr_imu="$WORK/late_imu.yaml"
expect_contains "$WORK/late2.txt" "topics /cam0/image_raw and /cam1/image_raw: no stereo pair"
[ -z "$(ls -A "$WORK/bad0" 2>/dev/null)" ] || fail "output left behind when nothing pairs"

# 5. Bad input: each error names the topic or the file, exits non-zero, leaves nothing.
expect_failure "$WORK/missing.txt" "$BIN/bag2rawlog" config.ini --set Bag2Rawlog.input_bag="$WORK/sim.bag" \
  --set Bag2Rawlog.output="$WORK/bad1/seq.rawlog" --set Bag2Rawlog.imu_topic=/imu_missing \
  --set Bag2Rawlog.kalibr_camchain="$WORK/sim_camchain.yaml" --set Bag2Rawlog.kalibr_imu="$WORK/sim_imu.yaml"
expect_contains "$WORK/missing.txt" "topic /imu_missing"
[ -z "$(ls -A "$WORK/bad1" 2>/dev/null)" ] || fail "output left behind for a missing topic"
head -c $(( $(stat -c %s "$WORK/sim.bag") / 2 )) "$WORK/sim.bag" > "$WORK/cut.bag"
cp "$WORK/sim_camchain.yaml" "$WORK/cut_camchain.yaml"; cp "$WORK/sim_imu.yaml" "$WORK/cut_imu.yaml"
expect_failure "$WORK/cut.txt" "$BIN/bag2rawlog" config.ini --set Bag2Rawlog.input_bag="$WORK/cut.bag" \
  --set Bag2Rawlog.output="$WORK/bad2/seq.rawlog" \
  --set Bag2Rawlog.kalibr_camchain="$WORK/cut_camchain.yaml" --set Bag2Rawlog.kalibr_imu="$WORK/cut_imu.yaml"
expect_contains "$WORK/cut.txt" "cut.bag"
[ -z "$(ls -A "$WORK/bad2" 2>/dev/null)" ] || fail "output left behind for a truncated bag"
cat "$WORK/late2.txt" "$WORK/missing.txt" "$WORK/cut.txt"
echo "OK"
