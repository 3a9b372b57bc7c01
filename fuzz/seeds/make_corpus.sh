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
# ROS 2 bags (../shared/data/ros2, read in place): the small MCAP and SQLite3 files as they are, and for the CDR
# target each message of the types bag2rawlog reads, after a byte naming the type (fuzz/targets/fuzz_cdr.cpp).
ros2="$SHARED/ros2"
if [ -d "$ros2" ]; then
  mkdir -p "$extra"/{fuzz_mcap,fuzz_sqlite_bag,fuzz_cdr}
  find "$ros2" -name '*.mcap' -size -64k | while read -r f; do cp "$f" "$extra/fuzz_mcap/$(echo "$f" | md5sum | cut -c1-12).mcap"; done
  find "$ros2" -name '*.db3' -size -64k | while read -r f; do cp "$f" "$extra/fuzz_sqlite_bag/$(echo "$f" | md5sum | cut -c1-12).db3"; done
  /usr/bin/python3 - "$ros2/rosbags_rs_all_types_sqlite3/test_bag_sqlite3.db3" "$extra/fuzz_cdr" <<'PY' || true
import sqlite3, sys
kinds = {"sensor_msgs/msg/Image": 0, "sensor_msgs/msg/CompressedImage": 1, "sensor_msgs/msg/Imu": 2,
         "sensor_msgs/msg/CameraInfo": 3, "geometry_msgs/msg/PoseStamped": 4, "geometry_msgs/msg/TransformStamped": 5,
         "nav_msgs/msg/Odometry": 6, "tf2_msgs/msg/TFMessage": 7}
db = sqlite3.connect("file:" + sys.argv[1] + "?immutable=1", uri=True)
rows = db.execute("SELECT t.type, m.id, m.data FROM messages m JOIN topics t ON t.id = m.topic_id")
for type_name, mid, data in rows:
    if type_name in kinds and len(data) <= 16000:
        open(f"{sys.argv[2]}/{kinds[type_name]}_{mid}", "wb").write(bytes([kinds[type_name]]) + data)
PY
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
