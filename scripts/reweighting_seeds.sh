#!/usr/bin/env bash
# Full against uniform reweighting of the structural factors (P + L + plane) over several realizations of the
# simulated sequences: Simulation.seed drives the world's textures, the LiDAR map's sampling and the image and IMU
# noise, so each seed is another draw of the same six flights. One seed decides little (differences of 0.03-0.1 cm
# between modes on one draw); this counts how often, and by how much, full reweighting wins.
#   bash scripts/reweighting_seeds.sh [duration_s=30] [out=out/reweighting_seeds] [seeds="ini 101 102"] [sequences...]
# Seed "ini" is the sequence's own (share/quasiloc/sim/<seq>.ini): its simulation is taken from out/sequences when
# there (scripts/track_sequences.sh, same duration). Other simulated folders, <out>/seed<k>/<seq>/sim, are reused when
# present. Writes <out>.md: ATE RMSE / max per sequence, seed and mode, and the count of runs where full has the
# lower RMSE.
set -euo pipefail
source "$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/track_variant.sh"
DURATION="${1:-30}"
OUT_ARG="${2:-out/reweighting_seeds}"
SEEDS="${3:-ini 101 102}"
shift 3 || shift $#
ablation_setup out/reweighting_seeds out/sequences "$OUT_ARG" "$@"
STRUCT=(--set MapFactors.map_points=true --set MapFactors.map_lines=true --set MapFactors.map_planes=true)
{
  echo "| sequence | seed | full | uniform | full lower |"
  echo "|---|---|---|---|---|"
} > "$OUT.md.tmp"
wins=0 cells=0 sum_full=0 sum_uniform=0
for seed in $SEEDS; do
  for seq in "${SEQS[@]}"; do
    root="$OUT/seed$seed"
    sim_root="$root"
    mkdir -p "$root/$seq"
    if [ "$seed" = ini ] && [ -s "$SEQ_ROOT/$seq/sim/gt.tum" ]; then
      sim_root="$SEQ_ROOT"
    elif [ ! -s "$root/$seq/sim/gt.tum" ]; then
      seed_arg=(); [ "$seed" = ini ] || seed_arg=(--set Simulation.seed="$seed")
      "$BIN/sim-rawlog" "share/quasiloc/sim/$seq.ini" --set Simulation.output_dir="$root/$seq/sim" "${seed_arg[@]}" \
        --set Simulation.duration_s="$DURATION" --set Simulation.inspection_png=false > "$root/$seq.sim.log"
    fi
    set -- $(track_variant "$sim_root" "$root" "$seq" full "${STRUCT[@]}" --set Reweighting.mode=full) \
      $(track_variant "$sim_root" "$root" "$seq" uniform "${STRUCT[@]}" --set Reweighting.mode=uniform)
    lower=$(awk -v f="$1" -v u="$3" 'BEGIN { print (f < u) ? "yes" : "no" }')
    [ "$lower" = yes ] && wins=$((wins + 1))
    cells=$((cells + 1))
    sum_full=$(awk -v s="$sum_full" -v a="$1" 'BEGIN { print s + a }')
    sum_uniform=$(awk -v s="$sum_uniform" -v a="$3" 'BEGIN { print s + a }')
    printf "| %s | %s | %s / %s | %s / %s | %s |\n" "$seq" "$seed" "$1" "$2" "$3" "$4" "$lower" | tee -a "$OUT.md.tmp"
  done
done
summary=$(awk -v w="$wins" -v n="$cells" -v f="$sum_full" -v u="$sum_uniform" \
  'BEGIN { printf "full reweighting has the lower ATE RMSE in %d of %d runs; mean RMSE full %.3f cm, uniform %.3f cm", w, n, f / n, u / n }')
echo "" >> "$OUT.md.tmp"
echo "$summary" | tee -a "$OUT.md.tmp"
mv "$OUT.md.tmp" "$OUT.md"
echo "table written to $OUT.md"
