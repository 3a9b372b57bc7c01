# The same 4 s flight tracked in the simulated room alone and inside a larger world: the room at the centre of a
# 3 x 3 grid of other simulated rooms 60 m apart (sim-large-world), with the sparse distance field and a 20 m region
# prior for the global start. The world must not change the result: the same start place, and the ATE within
# 0.1 cm of the room's. Bad input: an even grid is an error naming the key, and nothing is written.
source "$(dirname "$0")/common.sh"
SIM="$WORK/sim"
"$BIN/sim-rawlog" config.ini --set Simulation.output_dir="$SIM" --set Simulation.duration_s=4 \
  --set Simulation.inspection_png=false "${EXACT_MAP[@]}" > "$WORK/sim.txt"
# The other rooms at a quarter of the density: the test is about the layout, not the point count.
"$BIN/sim-large-world" share/quasiloc/sim/large_world.ini --set LargeWorld.base_map="$SIM/lidar_map.map" \
  --set LargeWorld.output="$WORK/world.map" --set LargeWorld.grid_cells=3 --set LargeWorld.spacing_m=60 \
  --set Lidar.density_per_m2=1500 > "$WORK/world.txt" || { cat "$WORK/world.txt"; fail "sim-large-world failed"; }
cat "$WORK/world.txt"
[ -s "$WORK/world.map" ] && [ -s "$WORK/world.map.ini" ] || fail "sim-large-world wrote no map or no .ini"
track() {  # track <output_dir> <map> [--set ...]: prints the ATE RMSE in cm
  local out="$1" map="$2"; shift 2
  "$BIN/quasiloc-track" config.ini --set Tracking.input_rawlog="$SIM/V1_01_easy.rawlog" \
    --set Tracking.calibration_ini="$SIM/calib.ini" --set Tracking.map_file="$map" \
    --set Tracking.groundtruth="$SIM/gt.tum" --set Tracking.output_dir="$out" \
    --set GeometricLocalization.field_layout=sparse "$@" > "$out.log" 2>&1 || { cat "$out.log"; fail "quasiloc-track failed"; }
  cat "$out.log" >&2
  json_value "$out/summary.json" ate.rmse_m --scale 100 --digits 3
}
# The prior: 20 m around a point 8 m from the start (the room's centre is about 1 m from the start).
PRIOR=(--set "Initialization.search_center_m=[6 -4 1]" --set Initialization.search_radius_m=20)
room=$(track "$WORK/room" "$SIM/lidar_map.map" "${PRIOR[@]}")
world=$(track "$WORK/world" "$WORK/world.map" "${PRIOR[@]}")
room_start=$(json_value "$WORK/room/summary.json" start.error_m --scale 100 --digits 2)
world_start=$(json_value "$WORK/world/summary.json" start.error_m --scale 100 --digits 2)
echo "ATE RMSE: room alone $room cm (start error $room_start cm), inside the world $world cm (start error $world_start cm)"
awk -v e="$world_start" 'BEGIN { exit !(e != "" && e < 10) }' || fail "start error in the world '$world_start' cm (>= 10)"
awk -v a="$room" -v b="$world" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(a != "" && b != "" && d <= 0.1) }' \
  || fail "the world changed the ATE: room $room cm, world $world cm (allowed 0.1 cm)"
awk -v a="$world" 'BEGIN { exit !(a != "" && a < 2.5) }' || fail "ATE in the world $world cm >= 2.5 cm"
# Bad input.
expect_failure "$WORK/bad.txt" "$BIN/sim-large-world" share/quasiloc/sim/large_world.ini \
  --set LargeWorld.base_map="$SIM/lidar_map.map" --set LargeWorld.output="$WORK/bad/world.map" \
  --set LargeWorld.grid_cells=4
expect_contains "$WORK/bad.txt" "[LargeWorld] grid_cells"
[ ! -e "$WORK/bad" ] || fail "output written despite the error"
echo "OK"
