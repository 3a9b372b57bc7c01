#!/usr/bin/env bash
# Relocalization latency, on the simulated sequences that scripts/track_sequences.sh left in <root> (reused, not
# simulated again): each is tracked from the start that global localization finds (init = global, as the main job),
# once as it is and once kidnapped (1 m / 10 deg, as if the track had silently gone wrong) at each of KIDNAP_TIMES;
# then a table per run (losses, unverified stretch, fix found in replay time, the live estimate of
# scripts/kidnap_live_latency.py, error of the last frame) in <out>.md.
#   bash scripts/track_sequences.sh 30 out/sequences        # once: the 30 s simulations
#   bash scripts/kidnap_latency.sh [root=out/sequences] [out=out/kidnap] [sequences...]
# KIDNAP_TIMES (environment, default "10 20", seconds after the start); TRACK_SETS: --set arguments added to every
# run, e.g. the relocalization's previous defaults: TRACK_SETS="--set Relocalization.relocalize_single_fix=false
# --set TrackMonitor.check_every=10 --set Relocalization.relocalize_near_m=1".
set -euo pipefail
# The kidnap is a test harness's: its program (quasiloc-track with [Kidnap]).
TRACK_PROGRAM=quasiloc-track-harness
source "$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/track_variant.sh"
ablation_setup out/kidnap "$@"
read -r -a TIMES <<< "${KIDNAP_TIMES:-10 20}"
read -r -a EXTRA <<< "${TRACK_SETS:-}"
for seq in "${SEQS[@]}"; do
  if [ ! -s "$SEQ_ROOT/$seq/sim/gt.tum" ]; then
    echo "kidnap_latency: $SEQ_ROOT/$seq/sim: no simulation (run scripts/track_sequences.sh 30 $SEQ_ROOT first)" >&2
    exit 1
  fi
  mkdir -p "$OUT/$seq"
  for k in -1 "${TIMES[@]}"; do
    run "$seq" "k$k" --set Initialization.init=global --set Kidnap.kidnap_at_s="$k" "${EXTRA[@]}" > /dev/null
  done
done
/usr/bin/python3 "$ROOT/scripts/kidnap_live_latency.py" "$OUT" | tee "$OUT.md"
