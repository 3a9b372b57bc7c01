#!/usr/bin/env bash
# Runs every fuzz target (fuzz/, docs/fuzzing.md) for N seconds each and prints a table:
# target, seconds, executions, corpus size, findings.
#
#     bash scripts/fuzz.sh <seconds> [target ...]      e.g. bash scripts/fuzz.sh 30; bash scripts/fuzz.sh 600 fuzz_pcd
#
# Builds the fuzz tree first if needed (clang, its own small CMake project: fuzz/CMakeLists.txt). The corpus of each
# target lives in <build>/corpus/<target>/ and grows between runs (seeded by fuzz/seeds/make_corpus.sh when empty);
# crashing inputs go to <build>/findings/<target>/. A target runs in chunks of at most QUASILOC_FUZZ_CHUNK seconds
# (libFuzzer keeps the corpus between chunks; a finding ends its chunk, the next chunk goes on).
# Environment:
#   QUASILOC_FUZZ_BUILD_DIR  the fuzz build folder (default <repo>/build-fuzz)
#   QUASILOC_FUZZ_JOBS       targets run at the same time (default 1; CI uses 2 on its 2 cores)
#   QUASILOC_FUZZ_CHUNK      seconds per libFuzzer run (default 60)
#   QUASILOC_FUZZ_LOCK       when set, each chunk holds a shared flock on this file (lets a timing run on the same
#                            machine take it exclusively between chunks)
# Exit status 1 when any target found something (the inputs are in the findings folder), 2 on a usage error.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${QUASILOC_FUZZ_BUILD_DIR:-$ROOT/build-fuzz}"
JOBS="${QUASILOC_FUZZ_JOBS:-1}"
CHUNK="${QUASILOC_FUZZ_CHUNK:-60}"

if [ $# -lt 1 ] || ! [[ "$1" =~ ^[0-9]+$ ]] || [ "$1" -lt 1 ]; then
  echo "usage: $0 <seconds per target> [target ...]" >&2
  exit 2
fi
SECONDS_PER_TARGET="$1"
shift

# Build (configure once; ninja rebuilds only what changed).
build_start=$(date +%s)
if [ ! -f "$BUILD/CMakeCache.txt" ]; then
  GENERATOR=()
  if command -v ninja >/dev/null 2>&1; then GENERATOR=(-G Ninja); fi
  CC=clang CXX=clang++ cmake -S "$ROOT/fuzz" -B "$BUILD" "${GENERATOR[@]}" -DQUASILOC_BUILD_FUZZERS=ON \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
fi
cmake --build "$BUILD" --parallel "$(nproc)"
echo "[fuzz] build took $(( $(date +%s) - build_start )) s"

bash "$ROOT/fuzz/seeds/make_corpus.sh" "$BUILD" "$BUILD/corpus"

targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  for t in "$BUILD"/bin/fuzz_*; do targets+=("$(basename "$t")"); done
fi
LOGS="$BUILD/logs"
mkdir -p "$LOGS"

# One target: chunks until its time is used; writes "<seconds> <executions> <findings>" to $LOGS/<target>.result.
run_target() {
  local t="$1" bin="$BUILD/bin/$1" corpus="$BUILD/corpus/$1" findings="$BUILD/findings/$1"
  [ -x "$bin" ] || { echo "[fuzz] no such target: $t" >&2; echo "0 0 1" > "$LOGS/$t.result"; return; }
  mkdir -p "$findings"
  local before left start execs=0 n
  before=$(find "$findings" -type f | wc -l)
  left="$SECONDS_PER_TARGET"
  start=$(date +%s)
  : > "$LOGS/$t.log"
  while [ "$left" -gt 0 ]; do
    local chunk=$(( left < CHUNK ? left : CHUNK ))
    local lock=()
    [ -n "${QUASILOC_FUZZ_LOCK:-}" ] && lock=(flock -s "$QUASILOC_FUZZ_LOCK")
    # -rss_limit_mb / -malloc_limit_mb: an allocation of more than 2 GB is a finding (a trusted length field);
    # -timeout: one input taking more than 10 s is a hang.
    "${lock[@]}" nice -n 19 "$bin" "$corpus" -max_total_time="$chunk" -timeout=10 -rss_limit_mb=2048 \
      -malloc_limit_mb=2048 -max_len=16384 -print_final_stats=1 -artifact_prefix="$findings/" \
      >>"$LOGS/$t.log" 2>&1 || true
    n=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$LOGS/$t.log" | tail -n 1 | grep -o '[0-9]*$' || echo 0)
    execs=$(( execs + ${n:-0} ))
    left=$(( SECONDS_PER_TARGET - ($(date +%s) - start) ))
    [ "$left" -gt 0 ] && [ -n "${QUASILOC_FUZZ_LOCK:-}" ] && sleep 3
  done
  echo "$(( $(date +%s) - start )) $execs $(( $(find "$findings" -type f | wc -l) - before ))" > "$LOGS/$t.result"
}

running=0
for t in "${targets[@]}"; do
  run_target "$t" &
  running=$(( running + 1 ))
  if [ "$running" -ge "$JOBS" ]; then
    wait -n || true
    running=$(( running - 1 ))
  fi
done
wait || true

status=0
printf '%-22s %8s %12s %8s %9s\n' target seconds executions corpus findings
for t in "${targets[@]}"; do
  read -r secs execs found < "$LOGS/$t.result"
  corpus=$(find "$BUILD/corpus/$t" -type f 2>/dev/null | wc -l)
  printf '%-22s %8s %12s %8s %9s\n' "$t" "$secs" "$execs" "$corpus" "$found"
  if [ "$found" -gt 0 ]; then status=1; fi
done
if [ "$status" -ne 0 ]; then
  echo "[fuzz] findings: see $BUILD/findings/<target>/ and $LOGS/<target>.log" >&2
fi
exit "$status"
