#!/usr/bin/env bash
# Installs every Debian package splam needs that is not installed yet (Debian 12).
# Safe to run again: it only calls apt-get when something is missing.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config clang-format
  libeigen3-dev libcgal-dev libceres-dev libboost-dev libboost-graph-dev
  libopencv-dev libcairo2-dev fonts-dejavu-core
  libyaml-cpp-dev libcli11-dev libfmt-dev nlohmann-json3-dev libdxflib-dev
  libgtest-dev libgmock-dev libbenchmark-dev valgrind
  librosbag-storage-dev libsensor-msgs-dev libnav-msgs-dev libtf2-msgs-dev python3
  libsqlite3-dev libzstd-dev liblz4-dev
  python3-ament-package
  clang libclang-rt-14-dev
  slurm-wlm munge chromium
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if ((${#missing[@]} == 0)); then
  echo "setup: all ${#packages[@]} packages present"
  exit 0
fi

echo "setup: installing ${missing[*]}"
sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
