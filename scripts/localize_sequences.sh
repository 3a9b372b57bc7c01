#!/usr/bin/env bash
# Global localization on the simulated sequences: for each sim-rawlog folder <root>/<seq>/sim (as
# scripts/track_sequences.sh leaves them), builds the room's database (share/quasiloc/reloc/sim_room.ini) and
# localizes every 10th frame twice: with the camera's left image, and with the quasi-image rendered at the
# ground-truth pose (the localization machinery without the camera-to-map modality gap). Fast and Full budgets.
#   bash scripts/localize_sequences.sh [root=out/sequences] [out=out/reloc]
# Writes <out>/<seq>/{room.qdb,camera/,quasi/} and the table <out>.md.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
ROOT="${1:-out/sequences}"
OUT="${2:-out/reloc}"
CFG=share/quasiloc/reloc/sim_room.ini
mkdir -p "$OUT"
{
  echo "# Global localization on the simulated sequences ($(date -u +%Y-%m-%d), $(nproc) cores)"
  echo
  echo "Database per sequence: $CFG (views rendered from that sequence's LiDAR map). Queries: every 10th frame."
  echo "Recall = localized within the threshold / queries; mATE over queries localized within 1 m; wrong = localized > 1 m off."
  echo
  echo "| sequence | views | build s | query | mode | queries | R@0.1 m | R@0.3 m | R@1.0 m | mATE cm | wrong | median ms |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
} > "$OUT.md"
for dir in "$ROOT"/*/sim; do
  seq=$(basename "$(dirname "$dir")")
  rawlog=$(ls "$dir"/*.rawlog | head -1)
  mkdir -p "$OUT/$seq"
  start=$(date +%s)
  build/bin/quasiloc-build-db $CFG --set BuildDatabase.map_file="$dir/lidar_map.map" \
    --set BuildDatabase.calibration_ini="$dir/calib.ini" --set BuildDatabase.output="$OUT/$seq/room.qdb" \
    > "$OUT/$seq/build-db.log" 2>&1
  build_s=$(( $(date +%s) - start ))
  views=$(sed -n 's/^database *\([0-9]*\) views.*/\1/p' "$OUT/$seq/build-db.log")
  for q in camera quasi; do
    build/bin/quasiloc-localize $CFG --set Localize.database="$OUT/$seq/room.qdb" --set Localize.input_rawlog="$rawlog" \
      --set Localize.groundtruth="$dir/gt.tum" --set Localize.map_file="$dir/lidar_map.map" \
      --set Localize.query_image=$q --set Localize.output_dir="$OUT/$seq/$q" > "$OUT/$seq/$q.log" 2>&1
    /usr/bin/python3 - "$OUT/$seq/$q/summary.json" "$seq" "$views" "$build_s" "$q" >> "$OUT.md" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
for m in s["modes"]:
    f = lambda v, k=1: "-" if v is None else f"{v:.{k}f}"
    print(f"| {sys.argv[2]} | {sys.argv[3]} | {float(sys.argv[4]):.0f} | {sys.argv[5]} | {m['mode']} | {m['evaluated']} | "
          f"{f(m['recall_0.1m'])} % | {f(m['recall_0.3m'])} % | {f(m['recall_1.0m'])} % | "
          f"{f(None if m['mate_m'] is None else 100 * m['mate_m'])} | {m['wrong_over_1m']} | {f(m['median_ms'])} |")
PY
  done
  echo "$seq done" >&2
done
cat "$OUT.md"
