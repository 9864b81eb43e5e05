#!/usr/bin/env bash
# Installs what lcjit needs on Debian 12 (only what is missing), then configures and builds.
# Usage: ./setup.sh                     (build into ./build)
#        ./setup.sh --install [PREFIX]  (then cmake --install into PREFIX, default /usr/local)
set -euo pipefail
cd "$(dirname "$0")"

packages=(
  cmake ninja-build g++ pkg-config
  ccache  # CMakeLists.txt: a second configuration or a rebuild compiles only what changed
  llvm-19-dev libclang-19-dev libclang-cpp19-dev clang-19 libclang-common-19-dev
  libpolly-19-dev  # LLVM's static libraries name Polly's: lcjit links them statically (start-up, CMakeLists.txt)
  hyperfine  # bench/vs_lpfg.py, bench/reload.py: paired timings (not used by the tests)
  libstdc++-12-dev libc6-dev zlib1g-dev libzstd-dev libedit-dev libffi-dev libxml2-dev libcurl4-openssl-dev
  libfmt-dev libcli11-dev libgtest-dev libbenchmark-dev libglm-dev libstb-dev
  libpng-dev libjpeg62-turbo-dev  # textures (stb_image only writes our own pictures)
  libclang-rt-19-dev  # the fuzzers' sanitizer and libFuzzer runtimes (bench/fuzz.sh, docs/fuzzing.md)
  libepoxy-dev libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri libglfw3-dev libimgui-dev
  libtinygltf-dev libtinyobjloader-dev nlohmann-json3-dev fonts-dejavu-core xvfb xdotool
  libfontconfig-dev libfreetype-dev fonts-urw-base35  # labels as Qt draws lpfg's (Times: Nimbus Roman)
  libavcodec-dev libavformat-dev libavutil-dev libswscale-dev  # videos (-out movie.mp4/.webm, --record): FFmpeg's H.264/VP9 encoders and muxers
  libharfbuzz-dev  # labels shaped (kerning, marks, any script) in pictures and the SVG/PS/PDF exports
  fonts-droid-fallback  # a face for CJK labels, fontconfig's fallback (tests/unit/text_test.cpp)
  libxml2-utils  # xmllint: the tests check that SVG with any label text is well-formed XML
  make  # reads a model folder's lpfg.mak (make -n: what lpfg would build), nothing else
  bubblewrap  # --sandbox (docs/security.md): the model's run in a child process without the user's files
  libyaml-cpp-dev  # sweep files (lcjit sweep, docs/sweeps.md)
  parallel  # GNU parallel: lcjit sweep run runs a sweep's tasks with it (and tests/run_sweep.sh)
  imagemagick  # import: tests/run_sandbox_window.sh's screenshots (without it its 7 tests are skipped)
  gdb  # tests/run_debugger.sh: lcjit --debugger under gdb
  contextfree  # Context Free's cfdg: the oracle of the CFDG tests (tests/cfdg); it brings libagg2
  ghostscript  # gs: tests/cfdg/run_pages.sh renders designs' PDF and PostScript pages to compare them with cfdg's PNG
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# AGG, which CFDG pictures are measured and drawn with (runtime/cfdg): Debian 12's libagg-dev
# conflicts with libagg2, which contextfree needs, so its package is unpacked here, not installed.
if [ ! -f .deps/agg/usr/include/agg2/agg_basics.h ]; then
  mkdir -p .deps/agg
  (cd .deps/agg && rm -f libagg-dev_*.deb && apt-get download -q libagg-dev && dpkg-deb -x libagg-dev_*.deb . && rm -f libagg-dev_*.deb)
fi

cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)"
if [ "${1:-}" = "--install" ]; then
  sudo=""
  [ "$(id -u)" -ne 0 ] && [ -z "${2:-}" ] && sudo="sudo"
  $sudo cmake --install build --prefix "${2:-/usr/local}"
fi
