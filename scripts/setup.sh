#!/usr/bin/env bash
# Installs the Debian 12 packages zbrdf needs to build, test and run, skipping those already
# installed. Run as root (or with sudo). Safe to run again.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  libeigen3-dev libceres-dev
  libopencv-core-dev libopencv-imgproc-dev libopencv-highgui-dev
  libopenexr-dev libtiff-dev libspng-dev nlohmann-json3-dev libyaml-cpp-dev zlib1g-dev
  libxxhash-dev
  libaravis-dev aravis-tools libusb-1.0-0-dev libx11-dev libxrandr-dev
  libgtest-dev libbenchmark-dev
  pybind11-dev python3-dev python3-numpy
  umockdev xvfb x11-utils
  clang libclang-rt-14-dev
  slurmctld slurmd slurm-client munge
  help2man
  chromium  # headless, for the report's browser test (tests/tools/report_browser_test.sh)
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]} == 0)); then
  echo "setup: all ${#packages[@]} packages already installed"
  exit 0
fi

if [[ $(id -u) -ne 0 ]]; then
  if command -v sudo >/dev/null; then SUDO=sudo; else
    echo "setup: need root to install: ${missing[*]}" >&2
    exit 1
  fi
else
  SUDO=
fi
echo "setup: installing ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
