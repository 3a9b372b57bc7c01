# A run without ground truth, scored afterwards from its files: the real EuRoC V1_01 micro set tracked with
# init = global twice, with and without [Tracking] groundtruth. Without it quasiloc-track exits 0, writes its outputs
# with no error fields (summary.json has no "ate" and no start error) and says so in one console line; the trajectory
# is the one the run with ground truth writes; quasiloc-eval on it and the ground truth (looked up as the frame source
# does: interpolated, within 5 ms) prints the ATE RMSE the run with ground truth printed, to the printed 0.001 cm.
# init = groundtruth without ground truth is an error that says why, with nothing written.
source "$(dirname "$0")/common.sh"
EUROC="$SHARED/data/euroc"
"$BIN/euroc2rawlog" --input "$EUROC/V1_01_easy_micro" --output "$WORK/micro.rawlog" \
  --groundtruth "$EUROC/groundtruth/cam0/V1_01_easy.txt" > "$WORK/convert.txt"
"$BIN/map-import" --input "$EUROC/maps/gmm/v1.gmm" --output "$WORK/v1.map" > "$WORK/map.txt"
GT="$WORK/micro_gt_cam0.tum"
track() {  # track <output_dir> <groundtruth or ""> [--set ...]
  local out="$1" gt="$2"; shift 2
  "$BIN/quasiloc-track" config.ini --set Tracking.input_rawlog="$WORK/micro.rawlog" \
    --set Tracking.calibration_ini="$WORK/micro_calib.ini" --set Tracking.map_file="$WORK/v1.map" \
    --set Tracking.groundtruth="$gt" --set Tracking.output_dir="$out" --set Tracking.write_scene=false \
    --set Initialization.init=global --set Relocalization.relocalize_latest_only=false "$@" > "$out.log" 2>&1 ||
    { cat "$out.log"; fail "quasiloc-track failed"; }
}
track "$WORK/gt" "$GT"
track "$WORK/nogt" ""
cat "$WORK/nogt.log"
# The run with ground truth: its printed ATE RMSE (cm, 3 decimals).
printed=$(sed -n 's/^ATE         RMSE \([0-9.]*\) cm.*/\1/p' "$WORK/gt.log")
[ -n "$printed" ] || { cat "$WORK/gt.log"; fail "the run with ground truth printed no ATE"; }
# The run without: outputs, no error fields, one line saying so.
for f in trajectory.tum diagnostics.csv summary.json quasiloc-track.ini initialization.txt; do
  [ -s "$WORK/nogt/$f" ] || fail "$f missing from the run without ground truth"
done
[ "$(grep -c "no ground truth given" "$WORK/nogt.log")" = 1 ] || fail "not exactly one 'no ground truth given' line"
expect_contains "$WORK/nogt.log" "quasiloc-eval --estimate $WORK/nogt/trajectory.tum --groundtruth"
! grep -q "^ATE         RMSE" "$WORK/nogt.log" || fail "an ATE printed without ground truth"
/usr/bin/python3 - "$WORK/nogt/summary.json" <<'PY' || fail "summary.json without ground truth holds error fields"
import json, sys
s = json.load(open(sys.argv[1]))
assert "ate" not in s, s.get("ate")
assert "error_m" not in s["start"] and "error_deg" not in s["start"], s["start"]
assert "nan" not in open(sys.argv[1]).read().lower()
PY
cmp -s "$WORK/gt/trajectory.tum" "$WORK/nogt/trajectory.tum" ||
  fail "the trajectory differs with and without ground truth (the estimator must not read it)"
# Scored afterwards from the files.
"$BIN/quasiloc-eval" --estimate "$WORK/nogt/trajectory.tum" --groundtruth "$GT" --association interpolated \
  --max-dt-s 0.005 --output-dir "$WORK/eval" > "$WORK/eval.log" || { cat "$WORK/eval.log"; fail "quasiloc-eval failed"; }
cat "$WORK/eval.log"
# (cm, 3 decimals; "-" where there is no figure: the standing MAV travels less than the 1 m of the RPE per metre)
read -r scored matched se3 sim3 rpe_m rpe_s < <(/usr/bin/python3 -c '
import json, sys
t = json.load(open(sys.argv[1]))["sequences"][0]
cm = lambda k: "-" if t.get(k) is None else "%.3f" % (100 * t[k])
print(cm("ate_rmse_m"), t["association"]["matched"], cm("ate_se3_rmse_m"), cm("ate_sim3_rmse_m"),
      cm("rpe_per_m_trans_rmse_m"), cm("rpe_per_s_trans_rmse_m"))' "$WORK/eval/report.json")
count=$(json_value "$WORK/gt/summary.json" ate.count)
echo "printed by quasiloc-track with ground truth: ATE $printed cm over $count poses; quasiloc-eval on the run" \
  "without: ATE $scored cm over $matched poses (SE(3) $se3 cm, Sim(3) $sim3 cm, RPE/m $rpe_m cm, RPE/s $rpe_s cm)"
[ "$matched" = "$count" ] || fail "quasiloc-eval paired $matched poses, quasiloc-track $count"
[ "$scored" = "$printed" ] || fail "quasiloc-eval's ATE $scored cm is not the printed $printed cm"
# init = groundtruth needs the ground truth: named, nothing written.
expect_failure "$WORK/bad.txt" "$BIN/quasiloc-track" config.ini --set Tracking.input_rawlog="$WORK/micro.rawlog" \
  --set Tracking.calibration_ini="$WORK/micro_calib.ini" --set Tracking.map_file="$WORK/v1.map" \
  --set Tracking.groundtruth= --set Tracking.output_dir="$WORK/bad" --set Initialization.init=groundtruth
expect_contains "$WORK/bad.txt" "[Tracking] groundtruth: is required with [Initialization] init = groundtruth"
[ ! -e "$WORK/bad" ] || fail "output written despite the error"
echo "OK"
