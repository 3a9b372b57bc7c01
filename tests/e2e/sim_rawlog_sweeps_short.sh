# sim-rawlog with [Lidar] map_source = sweeps: the map comes from simulated sweeps through map-build (a cheap run:
# every 20th sweep, half the azimuth steps, small cube maps); the printed figures are there and plausible; asking for
# the exact map's material labels with it is an error naming the key, with nothing written.
source "$(dirname "$0")/common.sh"
OUT="$WORK/sim"
CHEAP=(--set Lidar.map_source=sweeps --set Lidar.sweep_every=20 --set Lidar.sweep_azimuth_steps=900
  --set Lidar.sweep_cubemap_px=512 --set Simulation.duration_s=0.5)
"$BIN/sim-rawlog" share/quasiloc/sim/V1_01_easy.ini --set Simulation.output_dir="$OUT" "${CHEAP[@]}" \
  | tee "$WORK/log.txt"
[ -s "$OUT/lidar_map.map" ] || fail "no LiDAR map"
expect_contains "$WORK/log.txt" "swept map (simulated): mapping run"
expect_contains "$OUT/README.txt" "built by map-build from simulated sweeps"
grep -q "^map_source *= *sweeps" "$OUT/sim-rawlog.ini" || fail "the effective configuration lacks map_source = sweeps"
median_mm=$(sed -n 's/.*true surfaces median \([0-9.]*\) mm.*/\1/p' "$WORK/log.txt")
[ -n "$median_mm" ] || fail "no surface error printed"
awk -v m="$median_mm" 'BEGIN { exit !(m > 1 && m < 40) }' || fail "median error $median_mm mm, expected 1-40 mm"
expect_failure "$WORK/bad_log.txt" "$BIN/sim-rawlog" share/quasiloc/sim/V1_01_easy.ini \
  --set Simulation.output_dir="$WORK/sim2" "${CHEAP[@]}" --set Simulation.write_map_materials=true
expect_contains "$WORK/bad_log.txt" "write_map_materials"
[ ! -e "$WORK/sim2" ] || fail "output left behind for a refused configuration"
echo "OK"
