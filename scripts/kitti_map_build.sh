#!/usr/bin/env bash
# The real test of map-build (docs/map-build.md): the KITTI map built from the 39 raw scans of
# ../shared/data/kitti_raw_seq78/velodyne_even, with and without free-space carving, measured by
# scripts/kitti_map_build_check.py (smeared vehicle points removed, static structure kept); with BENCH=1 also the
# carving done by OctoMap (bench_carving), measured the same way.
#   bash scripts/kitti_map_build.sh [out_dir] [--set MapBuild.key=value]...   (from the repository root; ~1 min)
# Heavy enough for the CPU lock when others share the machine: flock /tmp/quasiloc.lock bash scripts/kitti_map_build.sh
set -euo pipefail
OUT="${1:-/tmp/quasiloc_kitti_map_build}"
shift || true
INI=rawlog_tools/map-build/kitti_raw_seq78.ini
mkdir -p "$OUT"
build/bin/map-build "$INI" --set MapBuild.output="$OUT/kitti_carved.map" --set MapBuild.export_cloud="$OUT/kitti_carved.ply" \
  --set MapBuild.export_removed="$OUT/kitti_removed.ply" "$@" | tee "$OUT/carved.log"
build/bin/map-build "$INI" --set MapBuild.output="$OUT/kitti_uncarved.map" --set MapBuild.export_cloud="$OUT/kitti_uncarved.ply" \
  --set MapBuild.carve=false "$@" | tee "$OUT/uncarved.log"
MAPS=("own=$OUT/kitti_carved.ply")
if [ "${BENCH:-0}" = 1 ]; then
  for m in own octomap; do
    build/bin/bench_carving "$INI" --set BenchCarving.method=$m --set BenchCarving.output_dir="$OUT" "$@" | tee "$OUT/bench_$m.log"
  done
  MAPS+=("octomap=$OUT/octomap_map.ply")
fi
/usr/bin/python3 scripts/kitti_map_build_check.py "$OUT/kitti_uncarved.ply" "${MAPS[@]}" \
  "given map_even_frames_5cm=../shared/data/kitti_raw_seq78/map_even_frames_5cm.ply" | tee "$OUT/check.txt"
