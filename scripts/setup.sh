#!/usr/bin/env bash
# Installs the Debian 12 packages the project builds and runs with. Does nothing when they are
# all present already. Run as root (or with sudo). --fuzz adds clang and libFuzzer
# (scripts/fuzz.sh).
set -euo pipefail

packages=(
  build-essential cmake
  libeigen3-dev libceres-dev libembree-dev libassimp-dev libyaml-cpp-dev
  libgtest-dev libbenchmark-dev libcli11-dev nlohmann-json3-dev
  python3-matplotlib python3-numpy
  # .npz archives: the AevaScenes point clouds (io/npz.cpp)
  libzip-dev pkg-config
  # Python bindings and their tests; Open3D and PCL's tools check the exports (tests/python).
  pybind11-dev python3-pytest python3-open3d pcl-tools
  # A one-node SLURM cluster the array-job test starts on this machine (tests/slurm), with munge
  # for its authentication; the test runs its own daemons and leaves the system's alone.
  slurm-wlm munge
  # MCAP: CRC-32 (zlib) and zstd chunks (io/src/mcap_*.cpp).
  zlib1g-dev libzstd-dev
)
# The independent MCAP reader test (tests/tools/mcap_js) runs Foxglove's npm libraries under
# node: Debian's nodejs and npm, unless a node with npm is installed already (NodeSource's
# nodejs bundles npm and conflicts with Debian's npm package).
if ! command -v node > /dev/null || ! command -v npm > /dev/null; then packages+=(nodejs npm); fi
if [ "${1:-}" = "--fuzz" ]; then packages+=(clang-14 libclang-rt-14-dev); fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages already installed"
  exit 0
fi

echo "setup: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
