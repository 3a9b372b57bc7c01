#!/usr/bin/env bash
# Tracking against the map: ablation of the map terms and the baselines, on the simulated sequences that
# scripts/track_sequences.sh left in <root> (reused, not simulated again). quasiloc-track with config.ini, all from
# the same ground-truth initial state ([Tracking] init = groundtruth; the tracker is deterministic: one run per cell):
#   full            the default: map edges as a window factor + the stereo points' distance to the map's surfaces
#   edges           the edge factor alone (stereo_map_factor = false)
#   surfaces        the stereo-to-surface factor alone (map_term = none: no edge alignment)
#   (the edge alignment's pose as a measurement, map_term = measurement, was measured worse and removed: its
#   figures are in docs/experiments.md)
#   VIO             visual-inertial odometry, same front-end, no map (map_updates = false)
#   IMU             IMU-only propagation (map_updates = false, temporal_landmarks = false)
#   bash scripts/track_baselines.sh [root=out/sequences] [out=out/baselines]
# Writes <out>/<seq>/<variant>/ (trajectory, diagnostics) and the table <out>.md (ATE RMSE / max in cm, map frame,
# no alignment).
set -euo pipefail
source "$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/track_variant.sh"
ablation_setup out/baselines "$@"
{
  echo "| sequence | full (edges + surfaces) | edges | surfaces | VIO, no map | IMU only |"
  echo "|---|---|---|---|---|---|"
} > "$OUT.md.tmp"
for dir in "$SEQ_ROOT"/*/sim; do
  seq=$(basename "$(dirname "$dir")")
  mkdir -p "$OUT/$seq"
  set -- $(run "$seq" full) \
    $(run "$seq" edges --set MapFactors.stereo_map_factor=false) \
    $(run "$seq" surfaces --set Tracking.map_term=none) \
    $(run "$seq" vio --set Tracking.map_updates=false) \
    $(run "$seq" imu --set Tracking.map_updates=false --set Tracking.temporal_landmarks=false)
  printf "| %s | %s / %s | %s / %s | %s / %s | %s / %s | %s / %s |\n" "$seq" "$1" "$2" "$3" "$4" \
    "$5" "$6" "$7" "$8" "$9" "${10}" | tee -a "$OUT.md.tmp"
done
mv "$OUT.md.tmp" "$OUT.md"
echo "table written to $OUT.md"
