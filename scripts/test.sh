#!/usr/bin/env bash
# The test command: set-up (packages, configure, build), then the whole ctest suite
# (unit tests and end-to-end program tests on ../shared data), then in CI (CI=true) every fuzz target for 20 s
# (scripts/fuzz.sh, docs/fuzzing.md; QUASILOC_FUZZ_SECONDS=N sets the time per target anywhere, 0 skips it).
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

# Fuzzing: its own small clang build (fuzz/), then each target for FUZZ_SECONDS, as many at a time as there are
# cores. A finding fails the run (the inputs are kept in build-fuzz/findings/).
FUZZ_SECONDS="${QUASILOC_FUZZ_SECONDS:-}"
if [ -z "$FUZZ_SECONDS" ] && [ "${CI:-}" = "true" ]; then FUZZ_SECONDS=20; fi
if [ -n "$FUZZ_SECONDS" ] && [ "$FUZZ_SECONDS" != "0" ]; then
  fuzz_start=$(date +%s)
  QUASILOC_FUZZ_JOBS="${QUASILOC_FUZZ_JOBS:-$(nproc)}" bash "$ROOT/scripts/fuzz.sh" "$FUZZ_SECONDS"
  echo "[test] fuzzing (build and ${FUZZ_SECONDS} s per target) took $(( $(date +%s) - fuzz_start )) s"
fi
