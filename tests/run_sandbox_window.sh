#!/usr/bin/env bash
# The window under --sandbox (docs/security.md): each picture is a sandboxed run's, sent back to
# the window. Under Xvfb. Usage: run_sandbox_window.sh LCJIT IMAGE_DIFF DIR CASE (DIR:
# tests/sandbox), CASE one of
#   same_picture  the sandboxed window shows the picture the in-process window shows
#   ssh           a model in the sandboxed window cannot read a key in the (fake) home's .ssh
#   faults        a crash, then --max-cpu, show as errors; the window stays up, and an edit runs
#   lab           --lab with a display says its runs are sandboxed, and shows the picture
#   esc           Esc stops a sandboxed run stuck in a loop; the window stays
#   input         a model reading the mouse is told it gets none; a MouseIns click is refused
#   animate       -a with an animation file: its first frame, Step by its step, Rewind, Run to the end
# Exit status 77 (skipped) where bubblewrap cannot make a sandbox or Xvfb tools are missing.
set -u
lcjit=$1 diff=$2 dir=$3 case=$4
if [ -z "${LCJIT_IN_XVFB:-}" ]; then
  bwrap --unshare-all --ro-bind / / true 2>/dev/null || { echo "skipped: bubblewrap cannot make a sandbox here"; exit 77; }
  for tool in xvfb-run xdotool import; do
    command -v $tool > /dev/null || { echo "skipped: $tool is missing"; exit 77; }
  done
  exec env LCJIT_IN_XVFB=1 xvfb-run -a -s "-screen 0 1024x768x24" "$0" "$@"
fi
work=$(mktemp -d)
pid=
trap '[ -n "$pid" ] && kill $pid 2>/dev/null; wait 2>/dev/null; rm -rf "$work"' EXIT
mkdir "$work/m" "$work/home"
cd "$work/m"
fail() { echo "FAIL: $*"; echo "--- stdout"; cat out.txt 2>/dev/null; echo "--- stderr"; cat err.txt 2>/dev/null; exit 1; }
start() { "$lcjit" "$@" > out.txt 2> err.txt & pid=$!; }
stop() { kill $pid; wait $pid 2>/dev/null; pid=; }
alive() { kill -0 $pid 2>/dev/null || fail "lcjit ended"; }
wait_err() {  # wait_err TEXT [N]: N lines (1) with TEXT, up to 120 s (a busy machine; the first run builds the cache)
  for _ in $(seq 1 1200); do
    [ "$(grep -cF -- "$1" err.txt)" -ge "${2:-1}" ] && return 0
    kill -0 $pid 2>/dev/null || break
    sleep 0.1
  done
  [ "$(grep -cF -- "$1" err.txt)" -ge "${2:-1}" ] || fail "not ${2:-1} line(s) with '$1' on stderr"
}
# The window's pixels, as X has them (Xvfb draws Mesa's picture into the window).
grab() { import -window "$(xdotool search --sync --name "lcjit: $1" | head -1)" "$2" 2>/dev/null; }
case $case in
  same_picture)
    cp "$dir/../../examples/tree.l" "$dir/../../examples/tree.v" "$dir/../../examples/tree.mat" .
    start -w 400 400 tree.v tree.mat tree.l
    # The in-process picture: once it has more than the background, and stays as it is.
    for _ in $(seq 1 600); do
      grab tree.l a.png && [ "$(convert a.png -format %k info:)" -gt 4 ] && sleep 0.5 && grab tree.l b.png &&
        "$diff" a.png b.png --threshold 0 --max-fraction 0 > /dev/null && break
      sleep 0.2
    done
    [ -f b.png ] || fail "no picture in the window"
    mv b.png plain.png
    stop
    start --sandbox -v -w 400 400 tree.v tree.mat tree.l
    wait_err "lcjit: sandboxed run shown: step"
    for _ in $(seq 1 600); do
      grab tree.l sandboxed.png && "$diff" plain.png sandboxed.png > diff.txt && break
      sleep 0.2
    done
    "$diff" plain.png sandboxed.png > diff.txt || fail "the pictures differ: $(cat diff.txt)"
    alive ;;
  ssh)
    mkdir -m 700 "$work/home/.ssh"
    echo "SECRET-KEY-4711" > "$work/home/.ssh/id_rsa"
    sed "s|SECRET_PATH|$work/home/.ssh/id_rsa|" "$dir/read_ssh.l" > read_ssh.l
    HOME="$work/home" start --sandbox -v read_ssh.l
    wait_err "lcjit: sandboxed run shown: step 1 of 1"
    alive
    stop
    grep -q "open failed: No such file or directory" out.txt || fail "the open did not fail"
    ! grep -rq "SECRET-KEY" out.txt err.txt . || fail "the key shows: $(grep -rl SECRET-KEY out.txt err.txt .)" ;;
  faults)
    cp "$dir/window_faults.l" m.l
    save() { sed "s/#define FAULT .*/#define FAULT $1/" m.l > tmp.l && mv tmp.l m.l; }
    start --sandbox -v --max-cpu 3 -rmode cont m.l
    # The statement's line, 10 (its columns count the line with FAULT expanded, as compile errors').
    wait_err ": error: production A(n) crashed in step 2: segmentation fault (null pointer dereference)"
    grep -F ": error: production A(n) crashed in step 2" err.txt | grep -qF "m.l:10:" || fail "the fault does not name line 10"
    alive
    save 0
    wait_err "lcjit: sandboxed run shown: step 3 of 3"
    alive
    save 2
    wait_err "m.l: error: the sandboxed run was stopped after step 1: it used its 3 s of CPU time (limit --max-cpu)"
    alive
    printf '#include <lpfgall.h>\nderivation length: 1;\naxiom: Oops;\n' > tmp.l && mv tmp.l m.l
    wait_err "m.l:3:"
    alive
    : > err.txt
    cp "$dir/window_faults.l" tmp.l && mv tmp.l m.l && save 0
    wait_err "lcjit: sandboxed run shown: step 3 of 3"
    alive ;;
  lab)
    cp "$dir/../../examples/tree.l" .
    cp tree.l good.l
    LCJIT_WINDOW_LAYOUT=$work/layout.txt HOME="$work/home" start --lab -v tree.l
    wait_err "every run is sandboxed"
    wait_err "lcjit: sandboxed run shown: step"
    # A broken edit: its error, in plain words first, over the last good picture (the window's
    # layout lists the message by its first line); the fix takes it away.
    printf '#include <lpfgall.h>\nderivation length: 1;\naxiom: Oops;\n' > tmp.l && mv tmp.l tree.l
    for _ in $(seq 1 1200); do grep -q "^message/tree.l, line 3: 'Oops' is not a declared module" "$work/layout.txt" && break; sleep 0.1; done
    grep -q "^message/tree.l, line 3: 'Oops' is not a declared module" "$work/layout.txt" || fail "no error over the picture: $(cat "$work/layout.txt")"
    alive
    : > err.txt
    cp good.l tmp.l && mv tmp.l tree.l
    wait_err "lcjit: sandboxed run shown: step"
    for _ in $(seq 1 600); do grep -q "^message/" "$work/layout.txt" || break; sleep 0.1; done
    grep -q "^message/" "$work/layout.txt" && fail "the error stayed after the fix: $(cat "$work/layout.txt")"
    alive ;;
  esc)
    cp "$dir/loop.l" .
    start --sandbox -w 400 400 loop.l
    for _ in $(seq 1 1200); do grep -q looping out.txt && break; sleep 0.1; done
    grep -q looping out.txt || fail "the model never reached its loop"
    xdotool mousemove --window "$(xdotool search --sync --name "lcjit: loop.l" | head -1)" 200 200
    xdotool key Escape
    wait_err "loop.l: the sandboxed run was stopped"
    alive ;;
  input)
    cp "$dir/mouse.l" .
    start --sandbox -w 400 400 mouse.l
    wait_err "lcjit: --sandbox: mouse.l: the model reads the window's input (GetMouseStatus/GetTabletStatus), which a sandboxed run does not get"
    xdotool mousemove --window "$(xdotool search --sync --name "lcjit: mouse.l" | head -1)" 200 200
    xdotool keydown shift keydown ctrl click 1 keyup ctrl keyup shift
    wait_err "lcjit: --sandbox: mouse insertion (MouseIns) changes the model's string, which lives in the sandboxed run; it is off"
    alive ;;
  animate)
    cp "$dir/window_faults.l" m.l
    sed -i "s/#define FAULT .*/#define FAULT 0/; s/derivation length: 3/derivation length: 6/" m.l
    printf 'first frame: 1\nstep: 2\n' > m.a
    start --sandbox -v -a -w 400 400 m.a m.l
    wait_err "lcjit: sandboxed run shown: step 1 of 6"
    xdotool mousemove --window "$(xdotool search --sync --name "lcjit: m.l" | head -1)" 200 200
    xdotool key ctrl+f
    wait_err "lcjit: sandboxed run shown: step 3 of 6"
    xdotool key ctrl+w
    wait_err "lcjit: sandboxed run shown: step 1 of 6" 2
    xdotool key ctrl+r  # Run: the frames to the end, then it stops
    wait_err "lcjit: sandboxed run shown: step 6 of 6"
    grep -q "step 5 of 6" err.txt || fail "Run did not show step 5"
    ! grep -qE "step (2|4) of 6" err.txt || fail "frames off the animation file's step were shown"
    alive ;;
  *) echo "unknown case $case"; exit 1 ;;
esac
echo "ok: $case"
