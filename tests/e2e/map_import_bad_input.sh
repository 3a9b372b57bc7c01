# Bad inputs: each gives an error naming the input, a non-zero exit, and no output file.
source "$(dirname "$0")/common.sh"
check_rejected() {
  local input="$1" what="$2"
  expect_failure "$WORK/log.txt" "$BIN/map-import" --input "$input" --output "$WORK/out.map"
  expect_contains "$WORK/log.txt" "$(basename "$input")"
  [ ! -e "$WORK/out.map" ] || fail "output left behind for $what"
  ls -a "$WORK" | grep -q "out.map.tmp" && fail "temporary left behind for $what"
  echo "rejected ($what): $(tail -1 "$WORK/log.txt")"
}
check_rejected "$WORK/missing.ply" "missing file"
echo "1 2 3" > "$WORK/cloud.unknownext"; check_rejected "$WORK/cloud.unknownext" "unknown format"
printf 'ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n1 1 1\n' > "$WORK/noint.ply"
check_rejected "$WORK/noint.ply" "no intensity field"
printf 'ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nproperty float intensity\nend_header\n0 nan 0 1\n1 1 1 1\n' > "$WORK/nan.ply"
check_rejected "$WORK/nan.ply" "NaN coordinates"
printf 'ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nproperty float intensity\nend_header\n' > "$WORK/empty.ply"
check_rejected "$WORK/empty.ply" "empty cloud"
echo "OK"
