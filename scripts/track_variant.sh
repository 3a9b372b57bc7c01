# Sourced by the ablation scripts: one quasiloc-track run of config.ini on a simulated sequence from its ground-truth
# initial state.
#   track_variant <seq_root> <out> <seq> <variant> [--set ...]: writes <out>/<seq>/<variant>/ and .log, prints
#   "RMSE max" (ATE, cm). Needs BIN (the programs' folder) and the repository root as the working directory.
track_variant() {
  local seq_root="$1" out="$2" seq="$3" variant="$4"; shift 4
  local sim="$seq_root/$seq/sim"
  "$BIN/${TRACK_PROGRAM:-quasiloc-track}" config.ini --set Tracking.input_rawlog="$(ls "$sim"/*.rawlog | head -1)" \
    --set Tracking.calibration_ini="$sim/calib.ini" --set Tracking.map_file="$sim/lidar_map.map" \
    --set Tracking.groundtruth="$sim/gt.tum" --set Tracking.output_dir="$out/$seq/$variant" \
    --set Initialization.init=groundtruth --set Tracking.write_scene=false "$@" > "$out/$seq/$variant.log" 2>&1
  /usr/bin/python3 scripts/json_figure.py "$out/$seq/$variant/summary.json" ate.rmse_m ate.max_m --scale 100 --digits 3
}

# ablation_setup <default_out> [root=out/sequences] [out=<default_out>] [sequences...]: the ablation scripts' common
# arguments. Sets ROOT, BIN (QUASILOC_BUILD_DIR/bin or build/bin), SEQ_ROOT, OUT and SEQS (the six simulated
# sequences unless given), enters the repository root and creates OUT.
ablation_setup() {
  local default_out="$1"; shift
  ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
  BIN="${QUASILOC_BUILD_DIR:-$ROOT/build}/bin"
  SEQ_ROOT="${1:-out/sequences}"
  OUT="${2:-$default_out}"
  shift 2 || shift $#
  SEQS=("$@")
  [ ${#SEQS[@]} -gt 0 ] || SEQS=(V1_01_easy V1_02_medium V1_03_difficult V2_01_easy V2_02_medium V2_03_difficult)
  cd "$ROOT"
  mkdir -p "$OUT"
}

# run <seq> <variant> [--set ...]: track_variant into the ablation's SEQ_ROOT and OUT.
run() { track_variant "$SEQ_ROOT" "$OUT" "$@"; }
