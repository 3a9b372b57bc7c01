# Sourced by the e2e scripts: BIN, SHARED, a scratch folder removed on exit, and assertion helpers.
set -euo pipefail
BIN="$1"
SHARED="$2"
WORK="$(mktemp -d /tmp/quasiloc_e2e.XXXXXX)"
trap '[ -n "${KEEP_WORK:-}" ] || rm -rf "$WORK"' EXIT

fail() { echo "FAIL: $*" >&2; exit 1; }
# expect_contains <file> <text>
expect_contains() { grep -qF -- "$2" "$1" || { echo "---- $1:"; cat "$1"; fail "'$2' not found in $1"; }; }
# expect_failure <logfile> <command...>: the command must exit non-zero
expect_failure() {
  local log="$1"; shift
  if "$@" >"$log" 2>&1; then cat "$log"; fail "expected a non-zero exit from: $*"; fi
}
# json_value <file.json> <path.to.key> [--scale 100 --digits 3]: a figure from a program's summary.json
json_value() { /usr/bin/python3 "$(dirname "${BASH_SOURCE[0]}")/../../scripts/json_figure.py" "$@" || fail "no $2 in $1"; }
# sim-rawlog's map for the tests of a program's mechanics: the exact sampler, a controlled experiment that takes 3 s
# to make; the default swept map takes 45 s and is tracked by track_swept_short.
EXACT_MAP=(--set Lidar.map_source=exact)
