#!/usr/bin/env bash
# The interactive window under Xvfb with -rmode cont: lcjit opens the model, a saved edit of the
# .l file (write to a temporary file, rename over: how editors save) recompiles and re-runs it in
# the same process (the model exports frame.obj at its end: 2 segments, then 5); a broken edit
# keeps the window and the last good model; fixing it runs again (7 segments).
# Usage: run_interactive.sh LCJIT MODEL
set -u
lcjit=$1 model=$2
work=$(mktemp -d)
# xvfb-run runs lcjit in its own process group (setsid): the trap ends both, pass or fail.
trap 'kill -- -$pid 2>/dev/null; rm -rf "$work"' EXIT
cp "$model" "$work/watched.l"
cd "$work"
command -v xvfb-run >/dev/null || { echo "xvfb-run is missing"; exit 1; }
setsid xvfb-run -a -s "-screen 0 1024x768x24" "$lcjit" -rmode cont watched.l > out.txt 2> err.txt &
pid=$!
segments() { [ -f frame.obj ] && grep -c '^v ' frame.obj || echo 0; }
wait_for() {  # wait_for N: frame.obj has N vertices (a chain of N-1 segments)
  for _ in $(seq 1 100); do [ "$(segments)" = "$1" ] && return 0; sleep 0.1; done
  echo "timed out waiting for $1 vertices (have $(segments))"; cat err.txt; exit 1
}
save() { sed "s/#define SEGMENTS .*/#define SEGMENTS $1/" watched.l > tmp.l && mv tmp.l watched.l; }
wait_for 3
save 5
wait_for 6
printf '#include <lpfgall.h>\nderivation length: 1;\naxiom: Oops;\n' > tmp.l && mv tmp.l watched.l
for _ in $(seq 1 50); do grep -q "watched.l:3:" err.txt && break; sleep 0.1; done
grep -q "watched.l:3:" err.txt || { echo "no error for the broken edit"; cat err.txt; exit 1; }
kill -0 $pid || { echo "lcjit died on a broken edit"; exit 1; }
cp "$model" tmp.l && sed -i "s/#define SEGMENTS .*/#define SEGMENTS 7/" tmp.l && mv tmp.l watched.l
wait_for 8
echo "ok: 2, 5 and 7 segments in one process; the broken edit was reported and survived"
