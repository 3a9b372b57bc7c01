#!/usr/bin/env bash
# Runs every fuzz target (fuzz/, docs/fuzzing.md) for N seconds each and prints a table:
# target, seconds, executions, corpus size, findings (in our code), mrpt (inside MRPT's deserialization).
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
#   QUASILOC_FUZZ_BUILD_LOCK when set, the build holds an exclusive flock on this file (a machine shared with builds)
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

# Build (configure once; ninja rebuilds only what changed), under QUASILOC_FUZZ_BUILD_LOCK when set.
build_start=$(date +%s)
build_lock=()
[ -n "${QUASILOC_FUZZ_BUILD_LOCK:-}" ] && build_lock=(flock "$QUASILOC_FUZZ_BUILD_LOCK")
if [ ! -f "$BUILD/CMakeCache.txt" ]; then
  GENERATOR=()
  if command -v ninja >/dev/null 2>&1; then GENERATOR=(-G Ninja); fi
  CC=clang CXX=clang++ "${build_lock[@]}" cmake -S "$ROOT/fuzz" -B "$BUILD" "${GENERATOR[@]}" \
    -DQUASILOC_BUILD_FUZZERS=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
fi
"${build_lock[@]}" cmake --build "$BUILD" --parallel "$(nproc)"
echo "[fuzz] build took $(( $(date +%s) - build_start )) s"

bash "$ROOT/fuzz/seeds/make_corpus.sh" "$BUILD" "$BUILD/corpus"

targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  for t in "$BUILD"/bin/fuzz_*; do targets+=("$(basename "$t")"); done
fi
LOGS="$BUILD/logs"
mkdir -p "$LOGS"

# Whose code a finding is in, from the chunk's log (a chunk stops at its first finding, so its log holds one
# report): "mrpt" when the first frame of the report outside the allocator, the sanitizers, libFuzzer and the system
# libraries (libc, libstdc++, the unwinder and ld.so, whose frames a timeout's stack starts with, OpenCV, libjpeg, ...)
# is in MRPT (libmrpt-*.so: its deserialization trusts length fields; docs/fuzzing.md), else "ours".
classify() {
  awk '
    /ERROR: (AddressSanitizer|libFuzzer|LeakSanitizer)|runtime error:/ { in_report = 1 }
    in_report && /^ *#[0-9]+ 0x/ {
      if ($0 ~ /__sanitizer|fuzzer::|__asan|asan_|libclang_rt|in (malloc|calloc|realloc|free|aligned_alloc|operator new|operator delete|__GI_|__run_exit_handlers|raise|abort|exit|_exit)[ (]|\.\/(stdlib|nptl|signal|csu)\/|libc\.so|libstdc\+\+|in std::|__gnu_cxx|libopencv|libjpeg|libpng|libz\.so|libgcc_s|in _dl_|[ (]elf\/|unknown module/) next
      print ($0 ~ /libmrpt-/ ? "mrpt" : "ours"); found = 1; exit
    }
    END { if (!found) print "ours" }
  ' "$1"
}

# The sanitizer's report of a finding in our code, cut to what a CI log needs to diagnose it (the input is kept only
# on the machine that ran it): the error line, the first frames and the SUMMARY line.
report_finding() {
  echo "---- $2"
  awk '/ERROR: (AddressSanitizer|libFuzzer|LeakSanitizer)|runtime error:|quasiloc fuzz:/ { on = 1 }
       on && (/^ *#[0-9]+ 0x/ ? ++frames <= 25 : 1) { print }
       /^SUMMARY:/ { exit }' "$1" | cut -c1-400
}

# One target: chunks until its time is used; writes "<seconds> <executions> <ours> <mrpt>" to $LOGS/<target>.result.
run_target() {
  local t="$1" bin="$BUILD/bin/$1" corpus="$BUILD/corpus/$1" findings="$BUILD/findings/$1"
  [ -x "$bin" ] || { echo "[fuzz] no such target: $t" >&2; echo "0 0 1 0" > "$LOGS/$t.result"; return; }
  mkdir -p "$findings"
  # A target's own settings, with the reason, in fuzz/targets/<target>.options: lines starting with '-' are more
  # libFuzzer flags, NAME=value lines environment variables (e.g. ASAN_OPTIONS), '#' lines comments.
  local extra=() env=()
  if [ -f "$ROOT/fuzz/targets/$t.options" ]; then
    read -r -a extra < <(grep '^-' "$ROOT/fuzz/targets/$t.options" | tr '\n' ' ') || true
    while IFS= read -r line; do env+=("$line"); done < <(grep -E '^[A-Z_]+=' "$ROOT/fuzz/targets/$t.options" || true)
  fi
  local left execs=0 fuzzed=0 ours=0 mrpt=0 n d chunk_start chunk_no=0
  left="$SECONDS_PER_TARGET"
  : > "$LOGS/$t.log"
  : > "$LOGS/$t.ours.txt"
  while [ "$left" -gt 0 ]; do
    local chunk=$(( left < CHUNK ? left : CHUNK )) chunk_log="$LOGS/$t.chunk.log" before
    before="$(ls "$findings")"
    chunk_start=$(date +%s)
    local lock=()
    [ -n "${QUASILOC_FUZZ_LOCK:-}" ] && lock=(flock -s "$QUASILOC_FUZZ_LOCK")
    # -rss_limit_mb / -malloc_limit_mb: an allocation of more than 2 GB is a finding (a trusted length field);
    # -timeout: one input taking more than 10 s is a hang.
    # UBSan prints no stack by default: with one, classify() can tell a report inside MRPT from one in our code.
    "${lock[@]}" env UBSAN_OPTIONS=print_stacktrace=1 "${env[@]}" nice -n 19 "$bin" "$corpus" -max_total_time="$chunk" -timeout=10 -rss_limit_mb=2048 \
      -malloc_limit_mb=2048 -max_len=16384 -print_final_stats=1 -artifact_prefix="$findings/" "${extra[@]}" \
      >"$chunk_log" 2>&1 || true
    cat "$chunk_log" >> "$LOGS/$t.log"
    n=$(grep -a -o 'stat::number_of_executed_units: *[0-9]*' "$chunk_log" | tail -n 1 | grep -o '[0-9]*$' || true)
    execs=$(( execs + ${n:-0} ))
    # Seconds fuzzed: libFuzzer's own count ("Done N runs in S second(s)", a wall time), or the chunk's wall time
    # when it stopped at a finding.
    d=$(grep -a -o 'Done [0-9]* runs in [0-9]* second' "$chunk_log" | tail -n 1 | grep -o 'in [0-9]*' | grep -o '[0-9]*' || true)
    d=${d:-$(( $(date +%s) - chunk_start ))}
    fuzzed=$(( fuzzed + (d > 0 ? d : 1) ))  # at least 1 s: a target that stops at once must not loop forever
    # New inputs in the findings folder (slow-unit-* files are reports of slow inputs, not findings).
    for f in $(comm -13 <(echo "$before") <(ls "$findings")); do
      case "$f" in slow-unit-*) continue ;; esac
      if [ "$(classify "$chunk_log")" = mrpt ]; then
        mrpt=$(( mrpt + 1 ))
        mkdir -p "$findings/mrpt" && mv "$findings/$f" "$findings/mrpt/"
      else
        ours=$(( ours + 1 ))
        report_finding "$chunk_log" "$findings/$f" >> "$LOGS/$t.ours.txt"
      fi
    done
    left=$(( SECONDS_PER_TARGET - fuzzed ))
    chunk_no=$(( chunk_no + 1 ))
    [ "$left" -gt 0 ] && [ -n "${QUASILOC_FUZZ_LOCK:-}" ] && sleep 3
  done
  rm -f "$LOGS/$t.chunk.log"
  echo "$fuzzed $execs $ours $mrpt" > "$LOGS/$t.result"
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
printf '%-22s %8s %12s %8s %9s %6s\n' target seconds executions corpus findings mrpt
for t in "${targets[@]}"; do
  read -r secs execs found mrpt < "$LOGS/$t.result"
  corpus=$(find "$BUILD/corpus/$t" -type f 2>/dev/null | wc -l)
  printf '%-22s %8s %12s %8s %9s %6s\n' "$t" "$secs" "$execs" "$corpus" "$found" "$mrpt"
  if [ "$found" -gt 0 ]; then status=1; fi
done
echo "[fuzz] findings: in our code (the run fails on any); mrpt: inside MRPT's deserialization (kept apart in"
echo "       <build>/findings/<target>/mrpt/, see docs/fuzzing.md)"
if [ "$status" -ne 0 ]; then
  for t in "${targets[@]}"; do
    [ -s "$LOGS/$t.ours.txt" ] && { echo "[fuzz] $t: findings in our code:"; cat "$LOGS/$t.ours.txt"; } >&2
  done
  echo "[fuzz] findings: see $BUILD/findings/<target>/ and $LOGS/<target>.log" >&2
fi
exit "$status"
