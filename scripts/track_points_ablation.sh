#!/usr/bin/env bash
# The point factor (tracking/map_points.h) alone and with the point-to-line factor, on the simulated sequences that
# scripts/track_sequences.sh left in <root>: quasiloc-track with config.ini from the ground-truth initial state,
# one run per cell (deterministic):
#   full            edges factor + stereo-to-surface factor (the default)
#   +P              plus point factors, the quasi-image's keypoints on its encoded gray image
#   +P matched      plus point factors, keypoints on the reflectivity matched to the camera's histogram
#   +P+L uniform    plus point factors (encoded gray) and map lines, line factors with weight 1
#   bash scripts/track_points_ablation.sh [root=out/sequences] [out=out/points_ablation] [sequences...]
# Writes <out>/<seq>/<variant>/ and the table <out>.md (ATE RMSE / max in cm, map frame, no alignment).
set -euo pipefail
source "$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/track_variant.sh"
ablation_setup out/points_ablation "$@"
{
  echo "| sequence | full (edges + surfaces) | + P | + P, matched reflectivity | + P + L, uniform |"
  echo "|---|---|---|---|---|"
} > "$OUT.md.tmp"
for seq in "${SEQS[@]}"; do
  mkdir -p "$OUT/$seq"
  set -- $(run "$seq" full) \
    $(run "$seq" points --set MapFactors.map_points=true --set Reweighting.mode=full) \
    $(run "$seq" points_matched --set MapFactors.map_points=true --set MapRefinement.quasi_gray=matched_reflectivity \
        --set Reweighting.mode=full) \
    $(run "$seq" points_lines_uniform --set MapFactors.map_points=true --set MapFactors.map_lines=true \
        --set Reweighting.mode=uniform)
  printf "| %s | %s / %s | %s / %s | %s / %s | %s / %s |\n" "$seq" "$1" "$2" "$3" "$4" "$5" "$6" "$7" "$8" \
    | tee -a "$OUT.md.tmp"
done
mv "$OUT.md.tmp" "$OUT.md"
echo "table written to $OUT.md"
