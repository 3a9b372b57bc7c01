# A missing input folder gives a clear error naming it, a non-zero exit, and no output.
source "$(dirname "$0")/common.sh"
expect_failure "$WORK/log.txt" "$BIN/euroc2rawlog" --input "$WORK/no_such_folder" --output "$WORK/out/x.rawlog"
expect_contains "$WORK/log.txt" "no_such_folder"
[ ! -e "$WORK/out/x.rawlog" ] || fail "a rawlog was left behind"
[ ! -e "$WORK/out/x_Images" ] || fail "an images folder was left behind"
# An IMU sensor.yaml without the noise model (here a camera's): the error names the file and the key.
expect_failure "$WORK/log2.txt" "$BIN/euroc2rawlog" --input "$SHARED/data/euroc/V1_01_easy_micro" \
  --output "$WORK/out2/x.rawlog" --imu-yaml "$SHARED/data/euroc/calib/cam0_sensor.yaml"
expect_contains "$WORK/log2.txt" "cam0_sensor.yaml: gyroscope_noise_density"
[ ! -e "$WORK/out2/x.rawlog" ] && [ ! -e "$WORK/out2/x_calib.ini" ] || fail "output was left behind"
# An IMU csv whose time goes back: the error names the file and the line.
cp -r "$SHARED/data/euroc/V1_01_easy_micro" "$WORK/bad_imu"
sed -i '101{h;d};102{G}' "$WORK/bad_imu/mav0/imu0/data.csv"
expect_failure "$WORK/log3.txt" "$BIN/euroc2rawlog" --input "$WORK/bad_imu" --output "$WORK/out3/x.rawlog"
expect_contains "$WORK/log3.txt" "imu0/data.csv"
[ ! -e "$WORK/out3/x.rawlog" ] || fail "a rawlog was left behind"
# A typo'd key in the INI: the error names the file, the section and the key; nothing is written.
printf '[Euroc2Rawlog]\ninput = %s\noutput = %s\nmax_frame = 3\n' "$SHARED/data/euroc/V1_01_easy_micro" \
  "$WORK/out4/x.rawlog" > "$WORK/typo.ini"
expect_failure "$WORK/log4.txt" "$BIN/euroc2rawlog" "$WORK/typo.ini"
expect_contains "$WORK/log4.txt" "typo.ini [Euroc2Rawlog] max_frame: unknown key"
[ ! -e "$WORK/out4/x.rawlog" ] || fail "a rawlog was left behind"
cat "$WORK/log2.txt" "$WORK/log3.txt" "$WORK/log4.txt"
echo "OK"
