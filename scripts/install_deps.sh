#!/usr/bin/env bash
# Installs the Debian 12 packages quasiloc needs, only those missing (apt, via sudo when not root).
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libopencv-dev libopencv-contrib-dev libceres-dev libtbb-dev
  libmrpt-system-dev libmrpt-io-dev libmrpt-config-dev libmrpt-math-dev libmrpt-poses-dev
  libmrpt-img-dev libmrpt-obs-dev libmrpt-maps-dev mrpt-apps
  libgtest-dev libbenchmark-dev
  # The fuzz targets (fuzz/, scripts/fuzz.sh, docs/fuzzing.md): clang with libFuzzer, ASan and UBSan.
  clang-14 libfuzzer-14-dev
  # The format_check test (tests/format_check.sh): the sources follow .clang-format.
  clang-format-14
  libyaml-cpp-dev
  # The system-call filter of the rawlog reader's child process (libs/dataset/src/isolated_object_child.cpp).
  libseccomp-dev
  # ROS 2 bags (bag2rawlog, rawlog2bag; libs/ros): rosbag2 SQLite3 storage, MCAP chunk compression and CRCs.
  libsqlite3-dev libzstd-dev liblz4-dev zlib1g-dev
  # ROS 1 bags without a ROS installation (bag2rawlog, rawlog2bag; libs/ros reads ROS 2 bags only without them).
  librosbag-dev libsensor-msgs-dev libgeometry-msgs-dev libnav-msgs-dev
  python3-numpy python3-matplotlib python3-opencv python3-scipy
  # map-build's carving benchmark (rawlog_tools/map-build/bench_carving.cpp: OctoMap against the product's own ray
  # casting; docs/map-build.md). Optional for the build: bench_carving is skipped without it.
  liboctomap-dev
  # The sharded database build's Slurm scripts (scripts/cluster/) and their e2e test, which starts its own
  # single-node Slurm with its own munge key and slurm.conf (scripts/cluster/local_slurm.sh); the packages' system
  # services are left unconfigured.
  slurm-wlm munge
  # Optional for the build (the LighterGlue matcher; see libs/frontend/CMakeLists.txt), installed so that the
  # tests exercise it: ~33 MB download, ~270 MB on disk, ~17 s to install.
  libtorch-dev
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "[install_deps] all ${#PACKAGES[@]} Debian packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then
    SUDO="sudo"
  else
    echo "[install_deps] error: missing packages (${missing[*]}) and not root, and sudo is not available" >&2
    exit 1
  fi
fi

echo "[install_deps] installing: ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "[install_deps] done"
