#!/usr/bin/env bash
# make_corpus.sh <build-fuzz dir> <corpus root>: fills <corpus root>/<target>/ with the seeds of every fuzz target,
# only for targets whose folder is empty or missing (libFuzzer grows the corpus in place between runs):
#  - small valid files written by our own writers (make_fuzz_seeds, fuzz/seeds/make_seeds.cpp);
#  - the checked-in hand-made seeds of fuzz/corpus/<target>/ (a few KB at most each);
#  - small pieces of the real test data in ../shared/data (sensor.yaml files, the first rows of EuRoC csv files and
#    of TUM ground truth) and the repository's INI files.
set -euo pipefail
BUILD="$1"
CORPUS="$2"
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
SHARED="${QUASILOC_SHARED_DIR:-$ROOT/../shared}/data"

generated="$(mktemp -d)"
trap 'rm -rf "$generated"' EXIT
"$BUILD/bin/make_fuzz_seeds" "$generated"
extra="$generated/extra"
mkdir -p "$extra"/{fuzz_sensor_yaml,fuzz_euroc_csv,fuzz_tum,fuzz_program_ini,fuzz_calibration_ini}
if [ -d "$SHARED/euroc" ]; then
  cp "$SHARED"/euroc/calib/*.yaml "$extra/fuzz_sensor_yaml/" 2>/dev/null || true
  micro="$SHARED/euroc/V1_01_easy_micro/mav0"
  [ -f "$micro/imu0/data.csv" ] && head -n 12 "$micro/imu0/data.csv" > "$extra/fuzz_euroc_csv/imu0.csv"
  [ -f "$micro/cam0/data.csv" ] && head -n 6 "$micro/cam0/data.csv" > "$extra/fuzz_euroc_csv/cam0.csv"
  body=$(ls "$SHARED"/euroc/groundtruth/body/*.csv 2>/dev/null | head -n 1 || true)
  [ -n "$body" ] && head -n 8 "$body" > "$extra/fuzz_euroc_csv/body.csv"
  cam0=$(ls "$SHARED"/euroc/groundtruth/cam0/*.txt 2>/dev/null | head -n 1 || true)
  [ -n "$cam0" ] && head -n 8 "$cam0" > "$extra/fuzz_tum/cam0_gt.txt"
fi
for ini in "$ROOT"/config.ini "$ROOT"/share/quasiloc/eval_example.ini "$ROOT"/share/quasiloc/reloc/*.ini; do
  [ -f "$ini" ] && [ "$(stat -c %s "$ini")" -le 8192 ] && cp "$ini" "$extra/fuzz_program_ini/" || true
done

for target_bin in "$BUILD"/bin/fuzz_*; do
  t="$(basename "$target_bin")"
  dir="$CORPUS/$t"
  mkdir -p "$dir"
  [ -n "$(ls -A "$dir")" ] && continue
  for src in "$generated/$t" "$ROOT/fuzz/corpus/$t" "$extra/$t"; do
    [ -d "$src" ] && cp "$src"/* "$dir/" 2>/dev/null || true
  done
  # A target with no seed at all still starts from one empty input.
  [ -n "$(ls -A "$dir")" ] || : > "$dir/empty"
done
