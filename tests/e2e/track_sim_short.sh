# quasiloc-track on a 5 s simulated V1_01 sequence (the top-level config.ini's world and settings): the ATE
# (map frame, no alignment) stays below a bound that the IMU alone (no map update, no temporal landmark)
# exceeds, so a broken estimator fails this test; and at least 90 % of the keyframes' map alignments are
# accepted, so a broken map alignment fails it too (visual-inertial odometry alone could meet the bound over 5 s).
# Then the same from a start found by global localization (init = global) instead of the ground truth.
source "$(dirname "$0")/common.sh"
# 2.5 cm (was 2.0 before the simulated IMU had real biases): the 5 s start from the ground truth is in motion, so
# the gyroscope bias (0.08 rad/s, prior 0 +- 0.1) is learned from the map over the first ~2 s (2.07 cm here).
BOUND_CM=2.5
SIM="$WORK/sim"
"$BIN/sim-rawlog" config.ini --set Simulation.output_dir="$SIM" --set Simulation.duration_s=5 \
  --set Simulation.inspection_png=false > "$WORK/sim.txt"
track() {  # track <output_dir> [--set ...]: prints the ATE RMSE in cm
  local out="$1"; shift
  "$BIN/quasiloc-track" config.ini --set Tracking.input_rawlog="$SIM/V1_01_easy.rawlog" \
    --set Tracking.calibration_ini="$SIM/calib.ini" --set Tracking.map_file="$SIM/lidar_map.map" \
    --set Tracking.groundtruth="$SIM/gt.tum" --set Tracking.output_dir="$out" "$@" > "$out.log" 2>&1 \
    || { cat "$out.log"; fail "quasiloc-track failed"; }
  cat "$out.log" >&2
  sed -n 's/^ATE *RMSE \([0-9.]*\) cm.*/\1/p' "$out.log"
}
ate=$(track "$WORK/track" --set Tracking.init=groundtruth)
for f in trajectory.tum diagnostics.csv quasiloc-track.ini scene.3Dscene; do [ -s "$WORK/track/$f" ] || fail "$f missing"; done
n=$(grep -vc '^#' "$WORK/track/trajectory.tum")
[ "$n" -ge 100 ] || fail "trajectory.tum has $n poses, expected >= 100 (5 s at 20 Hz)"
keyframes=$(sed -n 's/^frames .*keyframes \([0-9]*\), map updates accepted \([0-9]*\),.*/\1/p' "$WORK/track.log")
accepted=$(sed -n 's/^frames .*keyframes \([0-9]*\), map updates accepted \([0-9]*\),.*/\2/p' "$WORK/track.log")
[ -n "$keyframes" ] && [ $((100 * accepted)) -ge $((90 * keyframes)) ] \
  || fail "only $accepted of $keyframes map alignments accepted (expected >= 90 %)"
# Initialisation by global localization (no ground truth used to start): two frames localized by the stereo
# geometry against the map, agreeing with the gyroscope, give pose and velocity; the track must meet the bound too.
ate_global=$(track "$WORK/global" --set Tracking.init=global)
grep -q "pair closed" "$WORK/global/initialization.txt" || fail "initialization.txt does not record the closing pair"
start_cm=$(sed -n 's/^init start error \([0-9.]*\) cm.*/\1/p' "$WORK/global.log")
awk -v e="$start_cm" 'BEGIN { exit !(e != "" && e < 10) }' || fail "global start error '$start_cm' cm (expected < 10 cm)"
awk -v a="$ate_global" -v b="$BOUND_CM" 'BEGIN { exit !(a != "" && a < b) }' \
  || fail "tracked ATE RMSE after global initialisation $ate_global cm >= $BOUND_CM cm"
imu_only=$(track "$WORK/imu_only" --set Tracking.init=groundtruth --set Tracking.map_updates=false \
  --set Tracking.temporal_landmarks=false)
echo "ATE RMSE: tracked $ate cm ($accepted of $keyframes map updates accepted), after global initialisation $ate_global cm (start error $start_cm cm), IMU only $imu_only cm, bound $BOUND_CM cm"
awk -v a="$ate" -v b="$BOUND_CM" 'BEGIN { exit !(a != "" && a < b) }' || fail "tracked ATE RMSE $ate cm >= $BOUND_CM cm"
awk -v a="$imu_only" -v b="$BOUND_CM" 'BEGIN { exit !(a != "" && a > b) }' \
  || fail "the IMU alone ($imu_only cm) already meets the bound: the test would not catch a broken map term"
# Loss and recovery: at 2 s the tracker is restarted 1 m / 10 deg off with full confidence (as if it had silently
# gone wrong); the geometry check must notice, relocalize, and the last frame must be back within 5 cm.
# The search attempts every frame in order (relocalize_latest_only = false): the fixes, and so the figures below,
# are then the same on every machine. With the default (newest frame only) which frames are attempted depends on
# how fast the machine searches; a CI run under load attempted other frames than this machine does.
track "$WORK/kidnap" --set Tracking.init=groundtruth --set Tracking.kidnap_at_s=2 \
  --set Tracking.relocalize_latest_only=false > /dev/null
grep -q "relocalizations [1-9]" "$WORK/kidnap.log" || fail "the kidnapped tracker did not relocalize"
grep -q "single fix" "$WORK/kidnap/initialization.txt" \
  || fail "the relocalization did not restart from a single fix (relocalize_single_fix = true is the default)"
last_err=$(tail -1 "$WORK/kidnap/diagnostics.csv" | cut -d, -f12)
awk -v e="$last_err" 'BEGIN { exit !(e != "" && e < 0.05) }' || fail "after relocalization the last error is $last_err m"
# The loss must be noticed within the issue's 1 s: from the last check that confirmed the pose to the new start.
unverified=$(sed -n 's/.*longest unverified stretch \([0-9.]*\) s.*/\1/p' "$WORK/kidnap.log")
awk -v u="$unverified" 'BEGIN { exit !(u != "" && u < 1.0) }' || fail "the kidnapped track went unverified for '$unverified' s (>= 1 s)"
# ... and the runs that were not kidnapped must not have declared a loss.
for run in track global; do
  grep -q "^losses *0 " "$WORK/$run.log" || fail "the $run run declared a loss although it was not kidnapped"
done
# The restart re-tracks the frames since the relocalization's first fix: each frame once in the trajectory, in order.
awk '!/^#/ { if (n++ && $1 <= last) bad = 1; last = $1 } END { exit bad || n < 100 }' "$WORK/kidnap/trajectory.tum" \
  || fail "the kidnapped run's trajectory.tum repeats or reorders frames (or has < 100)"
echo "kidnapped at 2 s: relocalized, last frame's error $last_err m, unverified for $unverified s" \
  "($(sed -n 's/.*(fix found after \([0-9.]*\) s of replay).*/\1/p' "$WORK/kidnap.log") s of replay until the fix was found)"
# A false alarm: checks made to fail at the right pose (any share below 0.99 is examined, any gain fails). The
# tracker must go on tracking, the relocalization's fixes must confirm the track and withdraw the loss. The IMU's
# gyroscope bias is given as measured (the simulation's true start value, sigma 0.002 rad/s): in the first second of
# a start in motion with an unknown bias the track may be ~1 deg off, and a fix ~1 deg off the other way would
# then rightly not count as confirming it (max_correction_deg = 1.5), which is not what this part tests.
bias=$(awk -F, '!/^#/ { printf "[%s %s %s]", $2, $3, $4; exit }' "$SIM/gt_imu_bias.csv")
sed "s/^gyroscope_bias = .*/gyroscope_bias = $bias/; s/^gyroscope_bias_sigma = .*/gyroscope_bias_sigma = 0.002/" \
  "$SIM/calib.ini" > "$WORK/calib_known_bias.ini"
grep -q "^gyroscope_bias = \[-0.00" "$WORK/calib_known_bias.ini" || fail "no gyroscope bias written into the calibration"
track "$WORK/alarm" --set Tracking.init=groundtruth --set Tracking.lost_explained_ratio=0.99 \
  --set Tracking.lost_min_gain=0.0001 --set Tracking.lost_explained_floor=0 \
  --set Tracking.calibration_ini="$WORK/calib_known_bias.ini" > /dev/null
grep -q "^losses *[1-9][0-9]* (withdrawn [1-9]" "$WORK/alarm.log" || fail "no loss was withdrawn on a false alarm"
grep -q "relocalizations 0)" "$WORK/alarm.log" || fail "a false alarm restarted the tracker"
ate_alarm=$(sed -n 's/^ATE *RMSE \([0-9.]*\) cm.*/\1/p' "$WORK/alarm.log")
awk -v a="$ate_alarm" -v b="$BOUND_CM" 'BEGIN { exit !(a != "" && a < b) }' || fail "ATE $ate_alarm cm after false alarms"
echo "false alarms: $(grep '^losses' "$WORK/alarm.log"), ATE $ate_alarm cm"
# Bad input: a missing map is named, nothing is written.
expect_failure "$WORK/bad.txt" "$BIN/quasiloc-track" config.ini --set Tracking.input_rawlog="$SIM/V1_01_easy.rawlog" \
  --set Tracking.calibration_ini="$SIM/calib.ini" --set Tracking.groundtruth="$SIM/gt.tum" \
  --set Tracking.map_file="$WORK/nope.map" --set Tracking.output_dir="$WORK/bad"
expect_contains "$WORK/bad.txt" "nope.map"
[ ! -e "$WORK/bad" ] || fail "output written despite the error"
echo "OK"
