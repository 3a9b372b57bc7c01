# map-import on a GMMLoc Gaussian-mixture map (.gmm): the EuRoC room 1 sampled on its components' surfaces,
# checked against the room's 3D line map (same Leica scan); truncated or malformed .gmm files are rejected.
source "$(dirname "$0")/common.sh"
GMM="$SHARED/data/euroc/maps/gmm/v1.gmm"
"$BIN/map-import" --input "$GMM" --output "$WORK/v1.map" --export "$WORK/v1.ply" | tee "$WORK/gmm.txt"
[ -s "$WORK/v1.map" ] && [ -s "$WORK/v1.map.ini" ] && [ -s "$WORK/v1.ply" ] || fail "outputs not written"
expect_contains "$WORK/gmm.txt" "3299 Gaussian components"
expect_contains "$WORK/gmm.txt" "3205 sampled, 94 skipped as not flat"
expect_contains "$WORK/gmm.txt" "reflectivity constant 0.5"
grep -Eq '^gmm_density_per_m2 *= *2500 ' "$WORK/v1.map.ini" || { cat "$WORK/v1.map.ini"; fail "gmm_density_per_m2 not 2500"; }
points=$(sed -n 's/^sampled *\([0-9]*\) points.*/\1/p' "$WORK/gmm.txt")
[ "$points" -gt 850000 ] && [ "$points" -lt 920000 ] || fail "unexpected point count $points"
# Same seed, same map; format=gmm works whatever the extension; the density option is honoured.
cp "$GMM" "$WORK/room.dat"
"$BIN/map-import" --input "$WORK/room.dat" --format gmm --output "$WORK/v1b.map" --gmm-density 400 > "$WORK/b.txt"
expect_contains "$WORK/b.txt" "400 points/m2"
"$BIN/map-import" --input "$GMM" --output "$WORK/v1c.map" > /dev/null
cmp -s "$WORK/v1.map" "$WORK/v1c.map" || fail "two imports with the same seed differ"
# Independent evidence: the line map extracted from the same scan lies on the sampled surfaces.
# (numpy and scipy come with scripts/install_deps.sh.)
/usr/bin/python3 "$(dirname "$0")/../../scripts/gmm_map_check.py" "$WORK/v1.ply" "$SHARED/data/euroc/maps/lines/v1_line_3d.txt" \
  --max-median-m 0.02
# Bad input: an error naming the file, a non-zero exit, nothing written.
# check_rejected <input> <what> <problem text> <what the message must name: the file, or the INI key> [flags...]
check_rejected() {
  local input="$1" what="$2" fragment="$3" names="$4"; shift 4
  expect_failure "$WORK/log.txt" "$BIN/map-import" --input "$input" --output "$WORK/out.map" "$@"
  expect_contains "$WORK/log.txt" "$names"
  expect_contains "$WORK/log.txt" "$fragment"
  [ ! -e "$WORK/out.map" ] && [ ! -e "$WORK/out.map.ini" ] || fail "output left behind for $what"
  ls -a "$WORK" | grep -q "out.map.*tmp" && fail "temporary left behind for $what"
  echo "rejected ($what): $(tail -1 "$WORK/log.txt")"
}
head -c 10000 "$GMM" > "$WORK/truncated.gmm"
check_rejected "$WORK/truncated.gmm" "truncated" "truncated protobuf data" "truncated.gmm"
printf 'not a gaussian mixture\n' > "$WORK/text.gmm"
check_rejected "$WORK/text.gmm" "malformed" "protobuf" "text.gmm"
: > "$WORK/empty.gmm"
check_rejected "$WORK/empty.gmm" "empty" "empty GMM file" "empty.gmm"
check_rejected "$WORK/missing.gmm" "missing" "cannot open GMM file" "missing.gmm"
check_rejected "$GMM" "intensity_scale with a GMM" "does not apply to .gmm input" "[MapImport] intensity_scale" \
  --intensity-scale 255
check_rejected "$GMM" "bad density" "is out of range (must be [1, 1000000])" "[MapImport] gmm_density_per_m2" \
  --gmm-density 0
check_rejected "$GMM" "a seed that is not a number" "is not a non-negative integer" "[MapImport] gmm_seed" \
  --gmm-seed 12abc
echo "OK"
