# quasiloc-build-db in 4 shards through Slurm: a single-node Slurm started for the test
# (scripts/cluster/local_slurm.sh: a fresh munge key, munged, a generated slurm.conf, slurmctld -D and slurmd -D in
# the background, stopped on exit whatever happens), then scripts/cluster/build_db_slurm.sh: an array job of 4
# shards and a merge job after them. The merged database, its views file and its effective configuration equal a
# single-process build's byte for byte. The simulated room, coarsely sampled (about 150 views) to keep the test short.
source "$(dirname "$0")/common.sh"
SLURM_DIR="$WORK/slurm"
trap 'bash scripts/cluster/local_slurm.sh stop "$SLURM_DIR" > /dev/null 2>&1 || true; [ -n "${KEEP_WORK:-}" ] || rm -rf "$WORK"' EXIT
start=$(date +%s)

"$BIN/sim-rawlog" config.ini --set Simulation.output_dir="$WORK/sim" --set Simulation.duration_s=0.5 \
  --set Simulation.inspection_png=false "${EXACT_MAP[@]}" > "$WORK/sim.txt" 2>&1 || { cat "$WORK/sim.txt"; fail "sim-rawlog failed"; }
ARGS=(share/quasiloc/reloc/sim_room.ini --set BuildDatabase.map_file="$WORK/sim/lidar_map.map"
  --set BuildDatabase.calibration_ini="$WORK/sim/calib.ini" --set BuildDatabase.output="$WORK/db/room.qdb"
  --set ViewSampling.grid_spacing_m=1.0 --set ViewSampling.heights_m=1.2 --set ViewSampling.num_headings=4)

# The reference: one process, then moved aside so that the Slurm build writes the same output path (the effective
# configuration records it).
"$BIN/quasiloc-build-db" "${ARGS[@]}" > "$WORK/single.log" 2>&1 || { cat "$WORK/single.log"; fail "single-process build failed"; }
tail -4 "$WORK/single.log"
kept=$(sed -n 's/^views .* \([0-9]*\) kept$/\1/p' "$WORK/single.log")
[ -n "$kept" ] || fail "no kept-view count in the single-process log"
mv "$WORK/db" "$WORK/single"

bash scripts/cluster/local_slurm.sh start "$SLURM_DIR" || fail "could not start a single-node Slurm"
source "$SLURM_DIR/env.sh"
sinfo
bash scripts/cluster/build_db_slurm.sh --shards 4 --cpus-per-task 1 --bin "$BIN" --logs "$WORK/logs" --timeout 80 \
  "${ARGS[@]}" | tee "$WORK/slurm.log" || { tail -20 "$WORK"/logs/*.log; fail "the Slurm build failed"; }
for i in 0 1 2 3; do expect_contains "$WORK/slurm.log" "shard $i/4: "; done
expect_contains "$WORK/slurm.log" "merge of 4 shards: $kept views"
for i in 0 1 2 3; do [ -s "$WORK/db/room.qdb.shard-$i-of-4" ] || fail "shard file $i missing"; done
for f in room.qdb room.qdb.views.tum room.qdb.ini; do
  cmp "$WORK/single/$f" "$WORK/db/$f" || fail "$f of the Slurm build differs from the single-process build's"
done
# A build whose shards fail: the script names each failed shard with its error, the merge never runs, exit non-zero.
expect_failure "$WORK/fail.log" bash scripts/cluster/build_db_slurm.sh --shards 4 --bin "$BIN" --logs "$WORK/fail_logs" \
  --timeout 60 "${ARGS[@]}" --set BuildDatabase.map_file="$WORK/missing.map" --set BuildDatabase.output="$WORK/fail/room.qdb"
cat "$WORK/fail.log"
for i in 0 1 2 3; do expect_contains "$WORK/fail.log" "shard $i/4 FAILED"; done
expect_contains "$WORK/fail.log" "missing.map' does not exist"
expect_contains "$WORK/fail.log" "no merge: a shard failed"
[ ! -e "$WORK/fail" ] || fail "the failed build wrote something"
echo "merged database == single-process database (room.qdb, .views.tum, .ini byte for byte); test took $(( $(date +%s) - start )) s"
echo "OK"
