#!/usr/bin/env bash
# Installs Acrolab's dependencies from Debian 12's packages (nothing else is downloaded). Works as
# root and through sudo; does nothing when everything is already installed.
# Usage: scripts/install-deps.sh [--main | --fuzz]
#   --main   only what `acrolab` itself needs (the README's first command, which also draws the
#            athlete over the sample's video): no test, benchmark or Qt packages.
#   --fuzz   everything, and clang with its sanitizer and libFuzzer runtime (scripts/fuzz.sh).
set -euo pipefail

# What the acrolab program needs to build: compiler, Eigen, Ceres, OpenMesh, FFmpeg's libraries
# (video), OpenCV's calibration modules (cameras), YAML, JSON, TOML and XML (calibrations),
# formatting, argument parsing, Cairo for the report's charts, SQLite and Nettle for the season
# library (acrolab library, batch), and VTK with an X server of its own
# (Xvfb) for the 3D views — the athlete over the video, filmstrips, comparisons. Debian's VTK
# development package is large (it depends on Java, MPI, GDAL and HDF5 development packages): about
# 190 packages of the main install's 670.
main_packages=(
  build-essential cmake pkg-config git ccache
  libeigen3-dev libceres-dev libopenmesh-dev
  libavformat-dev libavcodec-dev libswscale-dev libavutil-dev libavdevice-dev
  libyaml-cpp-dev nlohmann-json3-dev libfmt-dev libcli11-dev libcairo2-dev libtomlplusplus-dev
  libpugixml-dev libsqlite3-dev nettle-dev
  libopencv-calib3d-dev libopencv-imgproc-dev libopencv-imgcodecs-dev
  libvtk9-dev libjsoncpp-dev xvfb xauth
  libopencv-dnn-dev libflatbuffers-dev libonnx-dev libprotobuf-dev
)
# The pose networks (scripts/install-models.sh) come from the npm registry through `npm pack`;
# Debian's npm is installed only where no npm is on the PATH already.
if ! command -v npm >/dev/null 2>&1; then main_packages+=(npm); fi
# Everything else: ChArUco boards (OpenCV's contrib modules), the window (Qt and VTK's Qt module),
# the tests and their oracles (GoogleTest, Simbody, the ffmpeg command), the benchmarks.
full_packages=(
  libopencv-contrib-dev
  libvtk9-qt-dev qtbase5-dev
  ffmpeg
  libgtest-dev libgmock-dev libbenchmark-dev
  libsimbody-dev
)

packages=("${main_packages[@]}")
if [ "${1:-}" != "--main" ]; then packages+=("${full_packages[@]}"); fi
if [ "${1:-}" = "--fuzz" ]; then packages+=(clang libclang-rt-14-dev); fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} Debian packages present"
  exit 0
fi

if [ "$(id -u)" -eq 0 ]; then
  sudo=()
elif command -v sudo >/dev/null 2>&1; then
  sudo=(sudo)
else
  echo "install-deps: need root or sudo to install: ${missing[*]}" >&2
  exit 1
fi
echo "install-deps: installing ${#missing[@]} packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update -qq
"${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
