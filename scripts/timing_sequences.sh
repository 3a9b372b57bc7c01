#!/usr/bin/env bash
# The whole-sequence timing table (docs/benchmarks.md): tracks the main job (config.ini, 10 s), the six simulated 30 s
# sequences (scripts/track_sequences.sh) and the real EuRoC micro set (scripts/real_micro.sh), one after the other,
# then prints per-stage median / p90 / p95 / max for each run (scripts/timing_table.py).
#   bash scripts/timing_sequences.sh [output_root=out/timing]
# Run it with nothing else on the machine: the figures are wall times. Simulated folders and the micro rawlog are
# reused when present (under output_root). Needs a built tree (scripts/build.sh) and ../shared.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BIN="${QUASILOC_BUILD_DIR:-$ROOT/build}/bin"
OUT="${1:-out/timing}"
cd "$ROOT"
mkdir -p "$OUT"
[ -s out/sim/V1_01_easy_10s/gt.tum ] || "$BIN/sim-rawlog" config.ini > "$OUT/main_sim.log"
"$BIN/quasiloc-track" config.ini --set Tracking.output_dir="$OUT/main" --set Tracking.write_scene=false \
  > "$OUT/main.log"
bash scripts/track_sequences.sh 30 "$OUT/seq30"
bash scripts/real_micro.sh "$OUT/real_micro" > /dev/null
runs=("main job (simulated, 10 s)=$OUT/main")
for seq in V1_01_easy V1_02_medium V1_03_difficult V2_01_easy V2_02_medium V2_03_difficult; do
  runs+=("$seq (simulated, 30 s)=$OUT/seq30/$seq/track")
done
runs+=("real EuRoC V1_01 micro (95 frames)=$OUT/real_micro/track")
/usr/bin/python3 scripts/timing_table.py "${runs[@]}" | tee "$OUT/timing.md"
echo "table written to $OUT/timing.md"
