#!/usr/bin/env bash
# The point-to-line map factor (tracking/map_lines.h) and its reweighting, on the simulated sequences that
# scripts/track_sequences.sh left in <root>: quasiloc-track with config.ini from the ground-truth initial state,
# one run per cell (deterministic):
#   full            edges factor + stereo-to-surface factor (the default)
#   +L full         plus map lines, reweighted by observability and association distribution ([Reweighting] full)
#   +L uniform      plus map lines, every line factor with weight 1 ([Reweighting] mode = uniform)
#   +L observ.      plus map lines, observability alone ([Reweighting] mode = observability)
#   bash scripts/track_lines_ablation.sh [root=out/sequences] [out=out/lines_ablation] [sequences...]
# Writes <out>/<seq>/<variant>/ and the table <out>.md (ATE RMSE / max in cm, map frame, no alignment).
set -euo pipefail
source "$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/track_variant.sh"
ablation_setup out/lines_ablation "$@"
{
  echo "| sequence | full (edges + surfaces) | + lines, full reweighting | + lines, uniform | + lines, observability |"
  echo "|---|---|---|---|---|"
} > "$OUT.md.tmp"
for seq in "${SEQS[@]}"; do
  mkdir -p "$OUT/$seq"
  set -- $(run "$seq" full) \
    $(run "$seq" lines_full --set MapFactors.map_lines=true --set Reweighting.mode=full) \
    $(run "$seq" lines_uniform --set MapFactors.map_lines=true --set Reweighting.mode=uniform) \
    $(run "$seq" lines_observability --set MapFactors.map_lines=true --set Reweighting.mode=observability)
  printf "| %s | %s / %s | %s / %s | %s / %s | %s / %s |\n" "$seq" "$1" "$2" "$3" "$4" "$5" "$6" "$7" "$8" \
    | tee -a "$OUT.md.tmp"
done
mv "$OUT.md.tmp" "$OUT.md"
echo "table written to $OUT.md"
