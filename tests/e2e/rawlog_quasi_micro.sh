# rawlog-quasi on 30 real EuRoC frames (the last 9 have ground truth) and the room's GMM map: a quasi-image per frame
# with a pose; its effective configuration reproduces the run; a typo'd key, a mode name or a number that is not one,
# in either section, is an error naming file, section and key.
source "$(dirname "$0")/common.sh"
EUROC="$SHARED/data/euroc"
"$BIN/euroc2rawlog" --input "$EUROC/V1_01_easy_micro" --output "$WORK/in/seq.rawlog" --max-frames 30 \
  --groundtruth "$EUROC/groundtruth/cam0/V1_01_easy.txt" > /dev/null
"$BIN/map-import" --input "$EUROC/maps/gmm/v1.gmm" --output "$WORK/v1.map" --gmm-density 400 > /dev/null
cat > "$WORK/quasi.ini" <<INI
[RawlogQuasi]
input_rawlog = $WORK/in/seq.rawlog
map_file = $WORK/v1.map
groundtruth = $WORK/in/seq_gt_cam0.tum
output_rawlog = $WORK/out/quasi.rawlog
[QuasiImage]
point_size_m = 0.05
gray_mode = shaded_reflectivity
INI
"$BIN/rawlog-quasi" "$WORK/quasi.ini" | tee "$WORK/log.txt"
n=$(sed -n 's/^quasi-images written: \([0-9]*\) .*/\1/p' "$WORK/log.txt")
[ "${n:-0}" -ge 5 ] || fail "expected quasi-images for the frames with ground truth, got ${n:-none}"
# The effective configuration is read back strictly and gives the same rawlog and quasi-images.
grep -Eq '^gray_mode *= *shaded_reflectivity ' "$WORK/out/quasi_rawlog-quasi.ini" || fail "gray_mode not saved"
"$BIN/rawlog-quasi" "$WORK/out/quasi_rawlog-quasi.ini" --set RawlogQuasi.output_rawlog="$WORK/out2/quasi.rawlog" \
  > /dev/null
cmp "$WORK/out/quasi.rawlog" "$WORK/out2/quasi.rawlog" || fail "the effective configuration gives another rawlog"
diff -r "$WORK/out/quasi_Images" "$WORK/out2/quasi_Images" || fail "the effective configuration gives other images"
# rejected <text the error must contain> <sed expression applied to quasi.ini>
rejected() {
  sed "$2" "$WORK/quasi.ini" > "$WORK/bad.ini"
  sed -i "s|$WORK/out/|$WORK/out_bad/|" "$WORK/bad.ini"
  expect_failure "$WORK/bad_log.txt" "$BIN/rawlog-quasi" "$WORK/bad.ini"
  expect_contains "$WORK/bad_log.txt" "$1"
  [ ! -e "$WORK/out_bad" ] || fail "output left behind ($1)"
  echo "rejected: $(tail -1 "$WORK/bad_log.txt")"
}
rejected "bad.ini [RawlogQuasi] png_evry: unknown key" '/^\[RawlogQuasi\]/a png_evry = 2'
rejected "bad.ini [QuasiImage] point_size: unknown key" 's/^point_size_m/point_size/'
rejected "bad.ini [QuasiImage] gray_mode: 'shaded' is not one of luminance, value, shaded_reflectivity" \
  's/^gray_mode = .*/gray_mode = shaded/'
rejected "bad.ini [RawlogQuasi] max_gt_dt_s: 'abc' is not a finite number" '/^\[RawlogQuasi\]/a max_gt_dt_s = abc'
echo "OK"
