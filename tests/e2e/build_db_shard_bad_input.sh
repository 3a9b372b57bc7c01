# The sharded database build's bad input: each merge fails with a non-zero exit, an error naming the
# shard and what is wrong, and writes nothing: a missing shard (its index and file), a shard of another map, a shard
# built with other options, a merge configured with other options, a copied shard file. A shard process killed
# (SIGKILL) while it renders leaves no shard file, and the merge then reports that shard missing. Last, the good
# shards merge into the single-process database.
source "$(dirname "$0")/common.sh"
sim() {  # sim <folder> [--set ...]: the simulated room's map and calibration
  local out="$1"; shift
  "$BIN/sim-rawlog" config.ini --set Simulation.output_dir="$out" --set Simulation.duration_s=0.5 \
    --set Simulation.inspection_png=false "${EXACT_MAP[@]}" "$@" > "$out.txt" 2>&1 || { cat "$out.txt"; fail "sim-rawlog failed"; }
}
sim "$WORK/sim"
sim "$WORK/other" --set Lidar.num_stations=4  # another survey of the same room: another map
CFG=share/quasiloc/reloc/sim_room.ini
DB="$WORK/db/room.qdb"
ARGS=($CFG --set BuildDatabase.map_file="$WORK/sim/lidar_map.map" --set BuildDatabase.calibration_ini="$WORK/sim/calib.ini"
  --set BuildDatabase.output="$DB" --set ViewSampling.grid_spacing_m=1.0 --set ViewSampling.heights_m=1.2
  --set ViewSampling.num_headings=4)
build() { "$BIN/quasiloc-build-db" "${ARGS[@]}" "$@" > "$WORK/build.log" 2>&1 || { cat "$WORK/build.log"; fail "quasiloc-build-db $* failed"; }; }
for i in 0 1 2 3; do build --shard $i/4; tail -1 "$WORK/build.log"; done
mkdir -p "$WORK/good"
cp "$DB".shard-* "$WORK/good/"
restore() { rm -f "$DB".shard-*; cp "$WORK/good/"* "$WORK/db/"; }
# merge_fails <what> <expected text>... [-- extra arguments]: the merge exits non-zero naming it, and writes nothing.
merge_fails() {
  local what="$1"; shift
  local texts=() extra=()
  while [ $# -gt 0 ] && [ "$1" != -- ]; do texts+=("$1"); shift; done
  [ $# -gt 0 ] && { shift; extra=("$@"); }
  expect_failure "$WORK/merge.log" "$BIN/quasiloc-build-db" "${ARGS[@]}" --merge 4 "${extra[@]}"
  for t in "${texts[@]}"; do expect_contains "$WORK/merge.log" "$t"; done
  for f in "$DB" "$DB.views.tum" "$DB.ini"; do [ ! -e "$f" ] || fail "$(basename "$f") written despite the error ($what)"; done
  ls -a "$WORK/db" | grep -q '\.tmp-' && fail "temporary left behind ($what)"
  echo "rejected ($what): $(tail -1 "$WORK/merge.log")"
}

rm "$DB.shard-3-of-4"
merge_fails "a missing shard" "shard 3 missing" "room.qdb.shard-3-of-4' not found" "--shard i/4"
restore

"$BIN/quasiloc-build-db" "${ARGS[@]}" --set BuildDatabase.map_file="$WORK/other/lidar_map.map" --shard 2/4 > "$WORK/build.log" 2>&1 ||
  { cat "$WORK/build.log"; fail "the shard of the other map failed"; }
merge_fails "a shard of another map" "shard 2/4" "room.qdb.shard-2-of-4" "is from another map" "other/lidar_map.map"
restore

build --shard 1/4 --set BuildDatabase.image_blur_sigma_px=1.5
merge_fails "a shard built with other options" "shard 1/4" "was built with other options" \
  "[BuildDatabase] image_blur_sigma_px = 1.5 in the shard, 2.5 in the merge's configuration"
restore

merge_fails "a merge configured with other options" "shard 0/4" "[Vocabulary] branching = 10 in the shard, 8 in the merge's configuration" \
  -- --set Vocabulary.branching=8
# Options that do not change the database may differ: the workers.
build --shard 0/4 --set BuildDatabase.threads=1

cp "$DB.shard-0-of-4" "$DB.shard-2-of-4"
merge_fails "a copied shard file" "room.qdb.shard-2-of-4: holds shard 0/4, not shard 2/4"
restore

# A shard killed while it renders (a dense sampling, so that it is still rendering after its first progress line):
# no shard file, and the merge names it missing.
rm "$DB.shard-1-of-4"
"$BIN/quasiloc-build-db" "${ARGS[@]}" --set ViewSampling.grid_spacing_m=0.5 --set ViewSampling.heights_m="0.9 1.5" \
  --set ViewSampling.num_headings=8 --set BuildDatabase.threads=1 --shard 1/4 > "$WORK/killed.log" 2>&1 &
pid=$!
for _ in $(seq 600); do grep -q '^views ' "$WORK/killed.log" && break; kill -0 $pid 2>/dev/null || break; sleep 0.05; done
grep -q '^views ' "$WORK/killed.log" || { cat "$WORK/killed.log"; fail "the shard to kill never started rendering"; }
kill -KILL $pid
status=0; { wait $pid; } 2>/dev/null || status=$?
[ "$status" = 137 ] || { cat "$WORK/killed.log"; fail "the shard was not killed while rendering (exit $status)"; }
echo "killed shard 1/4 while rendering: $(grep '^views ' "$WORK/killed.log" | tail -1)"
[ ! -e "$DB.shard-1-of-4" ] || fail "a killed shard left a shard file"
merge_fails "a killed shard" "shard 1 missing" "room.qdb.shard-1-of-4' not found"
restore

# Bad command lines.
expect_failure "$WORK/cmd.log" "$BIN/quasiloc-build-db" "${ARGS[@]}" --shard 4/4
expect_contains "$WORK/cmd.log" "'4/4': the shard index i of i/N must be in [0, N)"
expect_failure "$WORK/cmd.log" "$BIN/quasiloc-build-db" "${ARGS[@]}" --merge 0
expect_contains "$WORK/cmd.log" "--merge 0"
expect_failure "$WORK/cmd.log" "$BIN/quasiloc-build-db" "${ARGS[@]}" --shard 1/4 --merge 4
expect_contains "$WORK/cmd.log" "give one of --shard i/N and --merge N"

# The good shards merge into the single-process database.
"$BIN/quasiloc-build-db" "${ARGS[@]}" --merge 4 > "$WORK/merge.log" 2>&1 || { cat "$WORK/merge.log"; fail "the merge of the good shards failed"; }
cat "$WORK/merge.log"
mkdir -p "$WORK/merged"
mv "$DB" "$DB.views.tum" "$DB.ini" "$WORK/merged/"
build
for f in room.qdb room.qdb.views.tum room.qdb.ini; do cmp "$WORK/merged/$f" "$WORK/db/$f" || fail "merged $f differs"; done
echo "OK"
