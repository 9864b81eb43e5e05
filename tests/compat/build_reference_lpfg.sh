#!/usr/bin/env bash
# Builds the reference lpfg, the program lcjit is compared with (tests/compat/compare_lpfg.py,
# bench/vs_lpfg.py): vlab's lpfg, its translator l2c and vlab's environmental programs, from a
# snapshot of vlab's source (the git repository AlgorithmicBotany/vlab), outside this repository.
# lpfg is GPL: nothing of it is kept here, and nothing built here is linked into lcjit.
#
#   VLAB_GIT_DIR=<bare git folder of a vlab snapshot> tests/compat/build_reference_lpfg.sh
#   LPFG_PREFIX   where it goes (default /opt/lpfg-ref); JOBS: make's jobs (default: every core)
#
# Run again, it does only what is out of date: packages already there are not installed, the source
# is exported again only for another commit, make rebuilds what changed. About 15 minutes on two
# cores. The result is laid out as vlab's binary distribution ($LPFG_PREFIX is its VLABROOT):
#   bin/      lpfg, l2c, preproc.sh, cmpl.sh and the environmental programs (honda81, ecosystem, …)
#   include/  the headers preproc.sh gives a model (lpfgall.h and what it includes)
#   config/   lpfg.mak, the makefile cmpl.sh compiles a model with (g++ -O3 into lsys.so)
#   share/shaders/  the GLSL lpfg's window loads
#   env.sh    the variables lpfg needs; `. $LPFG_PREFIX/env.sh`, then in a model's folder:
#             QT_QPA_PLATFORM=offscreen lpfg -b -out s.strb FILES   (a string)
#             xvfb-run -a -s "-screen 0 1024x768x24 -dpi 96" lpfg -w 400 420 -out p.png FILES
set -euo pipefail

vlab=${VLAB_GIT_DIR:?VLAB_GIT_DIR must name a bare git folder of a vlab snapshot}
prefix=${LPFG_PREFIX:-/opt/lpfg-ref}
jobs=${JOBS:-$(nproc)}
src=$prefix/src
say() { echo "build_reference_lpfg: $*"; }

# Debian packages: Qt 5 (widgets, OpenGL, print support) and its tools, GLUT/GLU, bison and flex
# for l2c; Xvfb, xwd, ImageMagick and xdotool for pictures of lpfg's window.
needed=(g++ make git python3 qtbase5-dev qt5-qmake qtbase5-dev-tools libqt5opengl5-dev freeglut3-dev
        libglu1-mesa-dev bison flex xvfb x11-apps imagemagick xdotool)
missing=()
for p in "${needed[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  say "installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get install -y -q "${missing[@]}" || { apt-get update -q && apt-get install -y -q "${missing[@]}"; }
fi

# The part of the snapshot lpfg needs: its qmake includes, the libraries it links, l2c, lpfg, the
# environmental programs, and the icon lpfg's resources name.
[ -d "$vlab" ] || { echo "build_reference_lpfg: no git folder at $vlab" >&2; exit 2; }
commit=$(git --git-dir "$vlab" rev-parse HEAD)
mkdir -p "$src"
if [ "$(cat "$src/.vlab-commit" 2>/dev/null)" != "$commit" ]; then
  say "exporting vlab $commit"
  git --git-dir "$vlab" archive "$commit" common.pri expand_my_name.pri config libs l2c lpfg ENVIRO \
    browser/Images/default-icon.png | tar -x -C "$src"
  echo "$commit" >"$src/.vlab-commit"
  rm -f "$src/Makefile"
fi

# A top-level qmake project of our own: vlab's builds every vlab program; this one only the
# libraries lpfg and the environmental programs link, then l2c, lpfg and ENVIRO, in that order.
project="TEMPLATE = subdirs
CONFIG += ordered
SUBDIRS = libs/misc libs/image libs/comm libs/platform libs/shapes libs/message libs/directoryWatcher l2c lpfg ENVIRO"
if [ "$(cat "$src/reference.pro" 2>/dev/null)" != "$project" ]; then
  printf '%s\n' "$project" >"$src/reference.pro"
  rm -f "$src/Makefile"
fi
cd "$src"
[ -f Makefile ] || qmake -qt=qt5 reference.pro 2>/dev/null || qmake reference.pro
say "make -j$jobs (log: $src/build.log)"
if ! make -j"$jobs" >build.log 2>&1; then
  grep -n "error\|\*\*\*" build.log | tail -20 >&2
  echo "build_reference_lpfg: make failed; see $src/build.log" >&2
  exit 1
fi

# Installed as vlab's distribution lays it out.
mkdir -p "$prefix/bin" "$prefix/include" "$prefix/config" "$prefix/share/shaders"
cp -p "$src"/.binaries/bin/* "$prefix/bin/"
install -m 755 "$src/lpfg/scripts/preproc.sh" "$src/lpfg/scripts/cmpl.sh" "$prefix/bin/"
cp -p "$src"/lpfg/include/*.h "$prefix/include/"
cp -p "$src/lpfg/scripts/lpfg.mak.Linux" "$prefix/config/lpfg.mak"
cp -p "$src"/lpfg/shaders/*.glsl "$prefix/share/shaders/"

# What lpfg reads from its environment: it runs preproc.sh, l2c and cmpl.sh from $VLABBIN (on
# PATH); preproc.sh includes from $LPFGRESOURCES/include; cmpl.sh uses $VLABCONFIGDIR/lpfg.mak
# unless the model has its own; the window's shaders are under $VLABROOT/share; a .e file's
# programs are looked up on PATH.
cat >"$prefix/env.sh" <<EOF
# The reference lpfg's environment (tests/compat/build_reference_lpfg.sh wrote this file).
export VLABROOT=$prefix
export VLABBIN=\$VLABROOT/bin VLABCONFIGDIR=\$VLABROOT/config LPFGPATH=\$VLABROOT LPFGRESOURCES=\$VLABROOT
export VLABTMPDIR=\${VLABTMPDIR:-/tmp}
case ":\$PATH:" in *":\$VLABBIN:"*) ;; *) export PATH="\$VLABBIN:\$PATH" ;; esac
EOF

for program in lpfg l2c honda81 ecosystem arvo chiba clover density density3d MonteCarlo QuasiMC multiple \
               ornament radiosity shadowpyramid soil takenaka; do
  [ -x "$prefix/bin/$program" ] || { echo "build_reference_lpfg: $program was not built" >&2; exit 1; }
done
say "done (vlab $commit): . $prefix/env.sh"
