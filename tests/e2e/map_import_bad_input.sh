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
# A typo'd key in the INI, or a format that is not one of the names: the error names the file, section and key.
printf '[MapImport]\ninput = %s\noutput = %s\nvoxel_size = 0.1\n' "$WORK/cloud.unknownext" "$WORK/out.map" > "$WORK/typo.ini"
expect_failure "$WORK/log.txt" "$BIN/map-import" "$WORK/typo.ini"
expect_contains "$WORK/log.txt" "typo.ini [MapImport] voxel_size: unknown key"
expect_failure "$WORK/log.txt" "$BIN/map-import" --input "$WORK/cloud.unknownext" --output "$WORK/out.map" --format las
expect_contains "$WORK/log.txt" "[MapImport] format: 'las' is not one of auto, ply, pcd, kitti, xyzi, gmm"
[ ! -e "$WORK/out.map" ] || fail "output left behind for a bad option"
# The effective configuration loads back: a second import with it writes the same map.
printf 'ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nproperty float intensity\nend_header\n0 0 0 10\n1 1 1 200\n' > "$WORK/ok.ply"
"$BIN/map-import" --input "$WORK/ok.ply" --output "$WORK/ok.map" --voxel 0.5 --export "$WORK/ok.pcd" \
  --export-encoding binary_compressed > /dev/null
"$BIN/map-import" "$WORK/ok.map.ini" --set MapImport.output="$WORK/ok2.map" --set MapImport.export_cloud= > /dev/null
cmp "$WORK/ok.map" "$WORK/ok2.map" || fail "the effective configuration does not reproduce the map"
grep -Eq '^export_encoding *= *binary_compressed ' "$WORK/ok.map.ini" || fail "export_encoding not saved by name"
echo "OK"
