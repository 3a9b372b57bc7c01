#!/usr/bin/env bash
# The real-sensor evidence in one run (about 45 min on 2 cores):
#   (a) the real EuRoC V1_01 micro set against the map sampled from the room's GMM (scripts/real_micro.sh);
#   (b) the six simulated sequences with realistic IMU biases ([IMU] bias = euroc_groundtruth), 30 s and whole;
#   (c) the semi-real V1_01 (the real IMU stream, images rendered along the real trajectory), whole flight.
#   bash scripts/real_sensor_tables.sh [output_root=out/real_sensors]
# Tables: <output_root>/seq30.md, <output_root>/whole.md (c is its first row) and the summary of (a) on the console.
# Simulations are reused when present. Needs a built tree (scripts/build.sh) and ../shared beside the repository.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
OUT="${1:-out/real_sensors}"
cd "$ROOT"
echo "== (a) real micro set"
bash scripts/real_micro.sh "$OUT/real_micro"
echo "== (b) six simulated sequences, 30 s"
bash scripts/track_sequences.sh 30 "$OUT/seq30"
echo "== (c) semi-real V1_01 (real IMU) and (b) the six whole flights"
bash scripts/track_sequences.sh 0 "$OUT/whole" V1_01_easy_real_imu V1_01_easy V1_02_medium V1_03_difficult \
  V2_01_easy V2_02_medium V2_03_difficult
echo "== losses per run"
grep -H "^losses" "$OUT"/seq30/*.track.log "$OUT"/whole/*.track.log
