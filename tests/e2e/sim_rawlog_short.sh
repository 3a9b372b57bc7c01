# sim-rawlog writes a 1 s sequence with every promised output, and rawlog-edit reads the rawlog; its effective
# configuration reproduces the sequence; a typo'd key is an error naming file, section and key.
source "$(dirname "$0")/common.sh"
OUT="$WORK/sim"
"$BIN/sim-rawlog" share/quasiloc/sim/V1_01_easy.ini --set Simulation.output_dir="$OUT" \
  --set Simulation.duration_s=1 "${EXACT_MAP[@]}" | tee "$WORK/log.txt"
for f in gt.tum gt_body.tum calib.ini README.txt; do [ -s "$OUT/$f" ] || fail "$f missing"; done
ls "$OUT"/*.rawlog >/dev/null || fail "no rawlog"
ls -d "$OUT"/*_Images >/dev/null || fail "no images folder"
ls "$OUT"/*.map >/dev/null || fail "no LiDAR map"
ls "$OUT"/*.png >/dev/null || fail "no inspection PNG"
n_gt=$(grep -vc '^#' "$OUT/gt.tum")
[ "$n_gt" -ge 20 ] && [ "$n_gt" -le 21 ] || fail "gt.tum has $n_gt poses, expected 20-21 for 1 s at 20 Hz"
n_body=$(grep -vc '^#' "$OUT/gt_body.tum")
[ "$n_body" -ge 200 ] && [ "$n_body" -le 201 ] || fail "gt_body.tum has $n_body poses, expected 200-201"
rawlog-edit --info -i "$(ls "$OUT"/*.rawlog | head -1)" > "$WORK/info.txt" 2>&1 || { cat "$WORK/info.txt"; fail "rawlog-edit cannot read it"; }
cat "$WORK/info.txt"
grep -Eq "stereo */ *2[01] */" "$WORK/info.txt" || fail "rawlog-edit does not count 20-21 stereo observations"
grep -Eq "imu */ *20[01] */" "$WORK/info.txt" || fail "rawlog-edit does not count 200-201 IMU observations"
# The effective configuration is read back strictly and gives the same sequence.
"$BIN/sim-rawlog" "$OUT/sim-rawlog.ini" --set Simulation.output_dir="$WORK/sim2" > /dev/null
for f in lidar_map.map V1_01_easy.rawlog gt.tum gt_body.tum gt_imu_bias.csv; do
  cmp "$OUT/$f" "$WORK/sim2/$f" || fail "the effective configuration gives another $f"
done
diff -r "$OUT/V1_01_easy_Images" "$WORK/sim2/V1_01_easy_Images" > /dev/null || fail "other images"
sed 's/^num_boxes *=/num_boxs =/' share/quasiloc/sim/V1_01_easy.ini > "$WORK/typo.ini"
expect_failure "$WORK/typo_log.txt" "$BIN/sim-rawlog" "$WORK/typo.ini" --set Simulation.output_dir="$WORK/sim3"
expect_contains "$WORK/typo_log.txt" "typo.ini [World] num_boxs: unknown key"
[ ! -e "$WORK/sim3" ] || fail "output left behind for a typo'd key"
cat "$WORK/typo_log.txt"
echo "OK"
