#!/usr/bin/env bash
# Installs every Debian package that lidarscout's build, tests, benchmarks, fuzzers, viewer
# and training use (idempotent), then configures and builds into build/.
# Usage: scripts/setup.sh [extra cmake arguments]
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(
  # toolchain
  build-essential cmake ninja-build pkg-config git clang libclang-rt-14-dev
  # core libraries
  libgtest-dev libgmock-dev libbenchmark-dev libcli11-dev libfmt-dev libspdlog-dev
  nlohmann-json3-dev libsimdjson-dev libnanoflann-dev libcgal-dev libgmp-dev libmpfr-dev libboost-dev
  liburing-dev libcurl4-openssl-dev libssl-dev libstb-dev libgdal-dev
  # tests of remote datasets: a local HTTP(S) server on loopback, a self-signed certificate
  nginx openssl
  # GIS: PROJ (reprojection, lon/lat), gdal-bin (gdalinfo / gdal_grid in tests and benchmarks)
  libproj-dev gdal-bin
  # neural network inference (LibTorch) with the fast OpenMP OpenBLAS
  libtorch-dev libopenblas0-openmp
  # viewer: window, GUI, OpenGL loader; Xvfb for headless tests of the window
  libglfw3-dev libimgui-dev libepoxy-dev xvfb xauth
  # training (run by /usr/bin/python3)
  python3 python3-torch python3-numpy
  # the Dask driver of `dem --block` (python/lidarscout_dask): Dask's distributed scheduler, GDAL's Python
  python3-distributed python3-gdal
  # `lidarscout serve`: its HTTP server (cpp-httplib) and gzip (zlib); headless chromium (SwiftShader
  # WebGL2) for the tests of its page
  libcpp-httplib-dev zlib1g-dev chromium
  # the plot of `bench_view --soak` (scripts/plot_soak.sh)
  gnuplot-nox
  # the Python module (src/python, built for /usr/bin/python3) and its tests
  pybind11-dev python3-dev python3-pytest
)

SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

# Tests of s3:// datasets: an S3 server on loopback that verifies AWS Signature V4 signatures
# (@20minutes/s3rver, a maintained fork of s3rver; the original does not check V4 signatures),
# run by node. npm comes with Debian's nodejs (apt's npm package) or with a NodeSource nodejs.
if ! command -v npm >/dev/null; then
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends nodejs npm
fi
if [ ! -d "$(npm root -g)/@20minutes/s3rver" ]; then
  $SUDO npm install -g --no-fund --no-audit @20minutes/s3rver@4.0.4
fi

# OpenBLAS with OpenMP threads: the reference BLAS that libtorch may pull in is ~5x slower.
if [ -x /usr/sbin/update-alternatives ] || command -v update-alternatives >/dev/null; then
  for alt in libblas.so.3-x86_64-linux-gnu liblapack.so.3-x86_64-linux-gnu; do
    target=$(update-alternatives --list "$alt" 2>/dev/null | grep openblas-openmp | head -n1 || true)
    [ -n "$target" ] && $SUDO update-alternatives --set "$alt" "$target" >/dev/null || true
  done
fi

cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "$@"
cmake --build build
echo "setup: built build/lidarscout"
