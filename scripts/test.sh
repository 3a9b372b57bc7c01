#!/usr/bin/env bash
# The test command: set-up (packages, configure, build), then the whole ctest suite
# (unit tests and end-to-end program tests on ../shared data).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${QUASILOC_BUILD_DIR:-$ROOT/build}"

start=$(date +%s)
bash "$ROOT/scripts/build.sh"
built=$(date +%s)
echo "[test] set-up and build took $((built - start)) s"

if [ ! -d "$ROOT/../shared/data" ]; then
  echo "[test] error: ../shared/data not found beside the repository ($ROOT/../shared)" >&2
  exit 1
fi

cd "$BUILD_DIR"
ctest --output-on-failure --timeout 300 -j "$(nproc)"
echo "[test] tests took $(( $(date +%s) - built )) s"
