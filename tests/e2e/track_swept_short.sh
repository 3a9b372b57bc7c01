# The product's path on the simulated world: sim-rawlog's default map, built by map-build from the simulated sweeps of
# a mapping run (range noise, drift, carved people, windows that return nothing), tracked with config.ini from a
# global start with no initial guess. map_term = auto must leave the edge term out on such a map (its surfaces are
# centimetres thick, and the edges rendered from them move by pixels); the start must be found within 10 cm and the
# track must stay within the bound, with no loss. Half the sweeps of the default (sweep_every = 8) keep it short.
source "$(dirname "$0")/common.sh"
SIM="$WORK/sim"
BOUND_CM=6
"$BIN/sim-rawlog" config.ini --set Simulation.output_dir="$SIM" --set Simulation.duration_s=4 \
  --set Simulation.inspection_png=false --set Lidar.sweep_every=8 > "$WORK/sim.txt" \
  || { cat "$WORK/sim.txt"; fail "sim-rawlog failed"; }
expect_contains "$WORK/sim.txt" "swept map (simulated): mapping run"
"$BIN/quasiloc-track" config.ini --set Tracking.input_rawlog="$SIM/V1_01_easy.rawlog" \
  --set Tracking.calibration_ini="$SIM/calib.ini" --set Tracking.map_file="$SIM/lidar_map.map" \
  --set Tracking.groundtruth="$SIM/gt.tum" --set Tracking.output_dir="$WORK/track" \
  --set Tracking.write_scene=false > "$WORK/track.log" 2>&1 || { cat "$WORK/track.log"; fail "quasiloc-track failed"; }
expect_contains "$WORK/track.log" "map term: none (auto: the map's reflectivity varies and its surfaces are thick"
start_cm=$(json_value "$WORK/track/summary.json" start.error_m --scale 100 --digits 2)
ate=$(json_value "$WORK/track/summary.json" ate.rmse_m --scale 100 --digits 3)
losses=$(json_value "$WORK/track/summary.json" losses)
echo "swept map: start error $start_cm cm, ATE RMSE $ate cm, $losses losses, bound $BOUND_CM cm"
awk -v e="$start_cm" 'BEGIN { exit !(e != "" && e < 10) }' || fail "global start error '$start_cm' cm (expected < 10 cm)"
[ "$losses" = 0 ] || fail "$losses losses on the swept map"
awk -v a="$ate" -v b="$BOUND_CM" 'BEGIN { exit !(a != "" && a < b) }' || fail "ATE RMSE $ate cm >= $BOUND_CM cm"
echo "OK"
