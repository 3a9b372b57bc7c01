# euroc2rawlog on the micro EuRoC folder: 95 stereo observations, 29,120 IMU observations, readable by
# rawlog-edit, calibration INI and ground truth written.
source "$(dirname "$0")/common.sh"
OUT="$WORK/euroc/V1_01_micro.rawlog"
"$BIN/euroc2rawlog" --input "$SHARED/data/euroc/V1_01_easy_micro" --output "$OUT" \
  --groundtruth "$SHARED/data/euroc/groundtruth/cam0/V1_01_easy.txt" | tee "$WORK/log.txt"
[ -s "$OUT" ] || fail "rawlog not written"
[ -d "$WORK/euroc/V1_01_micro_Images" ] || fail "images folder not written"
n_png=$(ls "$WORK/euroc/V1_01_micro_Images" | grep -c '\.png$')
[ "$n_png" -eq 190 ] || fail "expected 190 PNG files (95 stereo pairs), found $n_png"
rawlog-edit --info -i "$OUT" > "$WORK/info.txt" 2>&1 || { cat "$WORK/info.txt"; fail "rawlog-edit cannot read the rawlog"; }
cat "$WORK/info.txt"
# rawlog-edit lists "Sensor (Label/Occurs/Rate/Durat.) : <label> / <count> / ..." per sensor label.
grep -Eq "stereo */ *95 */" "$WORK/info.txt" || fail "rawlog-edit does not count 95 stereo observations"
grep -Eq "imu */ *29120 */" "$WORK/info.txt" || fail "rawlog-edit does not count 29120 IMU observations"
ls "$WORK/euroc/"*.ini >/dev/null 2>&1 || fail "no calibration / effective INI written"
ls "$WORK/euroc/"*.tum >/dev/null 2>&1 || fail "no ground-truth TUM written"
echo "OK"
