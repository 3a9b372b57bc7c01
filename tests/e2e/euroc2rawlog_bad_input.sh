# A missing input folder gives a clear error naming it, a non-zero exit, and no output.
source "$(dirname "$0")/common.sh"
expect_failure "$WORK/log.txt" "$BIN/euroc2rawlog" --input "$WORK/no_such_folder" --output "$WORK/out/x.rawlog"
expect_contains "$WORK/log.txt" "no_such_folder"
[ ! -e "$WORK/out/x.rawlog" ] || fail "a rawlog was left behind"
[ ! -e "$WORK/out/x_Images" ] || fail "an images folder was left behind"
echo "OK"
