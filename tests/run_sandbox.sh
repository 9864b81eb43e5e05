#!/usr/bin/env bash
# --sandbox (docs/security.md): what a sandboxed model cannot do, and that a sandboxed run is
# otherwise the same run. Usage: run_sandbox.sh LCJIT DIR CASE (DIR: tests/sandbox), CASE one of
#   ssh          a model cannot read a key in the (fake) home's .ssh
#   socket       nor connect to a port on this machine
#   link         nor read what a link in its folder points to outside it
#   output       nor write beside its -out file outside its folder
#   fork         nor start processes (a fork bomb, at most 2000 forks, gets none)
#   fill_disk    a file past --max-file-size stops the run, the file no larger
#   same_output  a normal model writes the same string with and without it; the cache is used
#   crash        a crash in model code is reported as without the sandbox
#   cpu          an endless loop is stopped by --max-cpu
#   ctrl_c       Ctrl-C interrupts the model in the sandbox
#   watch        --watch re-runs sandboxed, and a save stops a run that is out of date
#   home         a model folder that is the home folder is refused
#   unavailable  without bwrap: --sandbox is an error, --lab warns and runs
#   design       a Context Free design runs sandboxed: the same picture as without, a file it
#                imports from outside its folder unreadable, --watch redraws a saved edit
#   profile      --profile alone prints the sandboxed run's profile table; a profile file is refused
# Exit status 77 (skipped) where bubblewrap cannot make a sandbox.
set -u
lcjit=$1 dir=$2 case=$3
if [ "$case" != unavailable ] && ! bwrap --unshare-all --ro-bind / / true 2>/dev/null; then
  echo "skipped: bubblewrap cannot make a sandbox here"
  exit 77
fi
work=$(mktemp -d)
pid=
trap '[ -n "$pid" ] && kill $pid 2>/dev/null; rm -rf "$work"' EXIT
mkdir "$work/m" "$work/home"
cd "$work/m"
fail() { echo "FAIL: $*"; echo "--- stdout"; cat out.txt 2>/dev/null; echo "--- stderr"; cat err.txt 2>/dev/null; exit 1; }
expect() {  # expect STATUS MESSAGE [REST]: the exit status and a line of stderr (with REST after MESSAGE)
  [ "$status" = "$1" ] || fail "exit status $status, expected $1"
  grep -qF -- "$2" err.txt || fail "no '$2' in stderr"
  [ $# -lt 3 ] || grep -F -- "$2" err.txt | grep -qF -- "$3" || fail "no '$2…$3' in stderr"
}
case $case in
  ssh)
    mkdir -m 700 "$work/home/.ssh"
    echo "SECRET-KEY-4711" > "$work/home/.ssh/id_rsa"
    sed "s|SECRET_PATH|$work/home/.ssh/id_rsa|" "$dir/read_ssh.l" > read_ssh.l
    # Without the sandbox the model does read it: the check below means something.
    HOME="$work/home" "$lcjit" -b -out o.str read_ssh.l > out.txt 2> err.txt
    grep -q "read: SECRET-KEY-4711" out.txt || fail "the model does not read the key even without the sandbox"
    rm -rf .lcjit-cache o.str
    HOME="$work/home" "$lcjit" --sandbox -b -out o.str read_ssh.l > out.txt 2> err.txt; status=$?
    [ "$status" = 0 ] || fail "exit status $status"
    grep -q "open failed: No such file or directory" out.txt || fail "the open did not fail"
    ! grep -rq "SECRET-KEY" out.txt err.txt . || fail "the key shows: $(grep -rl SECRET-KEY out.txt err.txt .)" ;;
  socket)
    python3 -c 'import socket, sys, time
s = socket.socket(); s.bind(("127.0.0.1", 0)); s.listen(8)
print(s.getsockname()[1], flush=True); time.sleep(120)' > port.txt &
    pid=$!
    for _ in $(seq 1 600); do [ -s port.txt ] && break; sleep 0.05; done
    sed "s/PORT/$(cat port.txt)/" "$dir/socket.l" > socket.l
    "$lcjit" -b -out o.str socket.l > out.txt 2> err.txt
    grep -q "^connected" out.txt || fail "the model does not connect even without the sandbox"
    "$lcjit" --sandbox -b -out o.str socket.l > out.txt 2> err.txt; status=$?
    [ "$status" = 0 ] || fail "exit status $status"
    grep -q "connect failed" out.txt || fail "the model connected from the sandbox" ;;
  link)
    mkdir -m 700 "$work/home/.ssh"
    echo "SECRET-KEY-4711" > "$work/home/.ssh/id_rsa"
    cp "$dir/fork.l" .
    ln -s "$work/home/.ssh/id_rsa" key.v  # the folder's author's link to the user's key
    HOME="$work/home" "$lcjit" --sandbox -b -out o.str key.v fork.l > out.txt 2> err.txt; status=$?
    expect 1 "key.v: error: a link to '$work/home/.ssh/id_rsa', outside the model's folder; a sandboxed run does not follow it"
    ln -s "$work/home/.ssh/id_rsa" linked.l  # the model itself: its folder would be .ssh
    HOME="$work/home" "$lcjit" --sandbox -b -out o.str linked.l > out.txt 2> err.txt; status=$?
    expect 1 "linked.l: error: a link to '$work/home/.ssh/id_rsa', outside the model's folder"
    ! grep -q "SECRET-KEY" out.txt err.txt || fail "the key shows" ;;
  output)
    mkdir "$work/out"
    sed "s|OTHER_PATH|$work/out/planted.txt|" "$dir/write_beside.l" > write_beside.l
    "$lcjit" --sandbox -b -out "$work/out/o.str" write_beside.l > out.txt 2> err.txt; status=$?
    [ "$status" = 0 ] || fail "exit status $status"
    # (Under /tmp the model's write may go to the sandbox's own /tmp, and vanish with it.)
    [ ! -e "$work/out/planted.txt" ] || fail "the model wrote planted.txt beside its output"
    grep -q "A(0)" "$work/out/o.str" || fail "no output in $work/out/o.str"
    # A failed run leaves no output file behind (the sandbox made it empty for the bind).
    cp "$dir/../faults/crash.l" .
    "$lcjit" --sandbox -b -out "$work/out/crash.str" crash.l > out.txt 2> err.txt; status=$?
    [ "$status" = 1 ] || fail "exit status $status for the crash"
    [ ! -e "$work/out/crash.str" ] || fail "crash.str was left behind" ;;
  fork)
    cp "$dir/fork.l" .
    "$lcjit" --sandbox -b -out o.str fork.l > out.txt 2> err.txt; status=$?
    [ "$status" = 0 ] || fail "exit status $status"
    grep -q "^forks: 0 (Operation not permitted)" out.txt || fail "the model forked in the sandbox" ;;
  fill_disk)
    cp "$dir/fill_disk.l" .
    "$lcjit" --sandbox --max-file-size 4M -b -out o.str fill_disk.l > out.txt 2> err.txt; status=$?
    expect 1 "fill_disk.l: error: the sandboxed run was stopped before the first step: it wrote a file past the size limit of 4.00 MB (--max-file-size)"
    size=$(stat -c %s fill.bin)
    [ "$size" -le 4194304 ] || fail "fill.bin has $size bytes"
    [ ! -e o.str ] || fail "a string was written after the fault"
    # lcjit's own output is held to the limit too (and the run named where it died). It is
    # written whole or not at all: no tree.str, and no part of one left beside it.
    cp "$dir/../../examples/tree.l" .
    "$lcjit" --sandbox --max-file-size 8K -b -out tree.str tree.l > out.txt 2> err.txt; status=$?
    expect 1 "tree.l: error: the sandboxed run was stopped after the derivation (6 steps): it wrote a file past the size limit of 8.0 KB (--max-file-size)"
    [ ! -e tree.str ] || fail "tree.str was written: $(stat -c %s tree.str) bytes"
    [ -z "$(ls -A | grep tree.str)" ] || fail "left beside it: $(ls -A | grep tree.str)" ;;
  overrides)  # -D and --seed reach the sandboxed run: four steps, not the model's three
    cp "$dir/../overrides/m.l" "$dir/../overrides/m.vset" .
    "$lcjit" --sandbox -b -D STEPS=4 --seed 2 -out o.str m.vset m.l 2> err.txt || fail "the run failed"
    [ "$(tr '\n' ' ' < o.str)" = "F(1) F(1) F(1) F(1) A(4) " ] || fail "the string: $(cat o.str)" ;;
  same_output)
    cp "$dir/../../examples/tree.l" .
    "$lcjit" -b -out plain.str tree.l 2> err.txt || fail "the run without the sandbox failed"
    "$lcjit" --sandbox -b -out sandboxed.str tree.l 2> err.txt || fail "the sandboxed run failed"
    cmp plain.str sandboxed.str || fail "the strings differ"
    [ -d .lcjit-cache ] || fail "no cache in the model's folder"
    "$lcjit" --sandbox -v -b -out again.str tree.l 2> err.txt || fail "the second sandboxed run failed"
    grep -q "cached PCH" err.txt || fail "the second sandboxed run did not use the cache"
    cmp plain.str again.str || fail "the strings differ" ;;
  crash)
    cp "$dir/../faults/crash.l" .
    "$lcjit" --sandbox -b -out o.str crash.l > out.txt 2> err.txt; status=$?
    # The statement (line 8), at its '=' (column 24).
    expect 1 "crash.l:8:24: error: production A(n) crashed in step 3: segmentation fault (null pointer dereference)"
    [ ! -e o.str ] || fail "a string was written after the fault" ;;
  cpu)
    cp "$dir/../faults/loop.l" .
    "$lcjit" --sandbox --max-cpu 1 -b -out o.str loop.l > out.txt 2> err.txt; status=$?
    expect 1 "loop.l: error: the sandboxed run was stopped after step 1: it used its 1 s of CPU time (limit --max-cpu)" ;;
  ctrl_c)
    cp "$dir/loop.l" .
    "$lcjit" --sandbox -b -out o.str loop.l > out.txt 2> err.txt &
    pid=$!
    for _ in $(seq 1 2400); do grep -q looping out.txt && break; sleep 0.05; done
    grep -q looping out.txt || fail "the model never reached its loop"
    kill -INT $pid
    wait $pid; status=$?
    pid=
    expect 1 "loop.l:12:" ": error: production A(n) was interrupted in step 2" ;;  # in the loop, wherever
  watch)
    cp "$dir/loop.l" m.l
    "$lcjit" --sandbox --watch -out o.str m.l > out.txt 2> err.txt &
    pid=$!
    for _ in $(seq 1 2400); do grep -q looping out.txt && break; sleep 0.05; done
    grep -q looping out.txt || fail "the model never reached its loop"
    sed -i 's/n == 1/n == 100/' m.l  # the fix, saved while the old run loops
    for _ in $(seq 1 2400); do grep -q "reload 1" err.txt && break; sleep 0.05; done
    grep -q "reload 1 (m.l): ran in .* ms, wrote o.str" err.txt || fail "no reload after the fix"
    grep -q "A(5)" o.str || fail "o.str is not the fixed model's string" ;;
  home)
    cp "$dir/fork.l" .
    HOME="$work/m" "$lcjit" --sandbox -b -out o.str fork.l > out.txt 2> err.txt; status=$?
    expect 1 "lcjit: --sandbox: the model's folder '$work/m' holds your home folder" ;;
  unavailable)
    cp "$dir/../faults/crash.l" .
    sed -i 's/n == 2/n == 200/' crash.l
    env PATH=/nonexistent "$lcjit" --sandbox -b -out o.str crash.l > out.txt 2> err.txt; status=$?
    expect 1 "lcjit: --sandbox: bubblewrap (bwrap) is not installed (Debian: apt install bubblewrap)"
    [ ! -e o.str ] || fail "the model ran"
    env PATH=/nonexistent "$lcjit" --lab -b -out o.str crash.l > out.txt 2> err.txt; status=$?
    expect 0 "lcjit: warning: --lab runs without a sandbox: bubblewrap (bwrap) is not installed"
    grep -q "A(5)" o.str || fail "--lab did not run the model"
    # With a display and no sandbox, --lab is the REPL with the window: the model opens derived
    # to its end, as lpfg opens it (not at step 0).
    if command -v xvfb-run >/dev/null && [ "${LCJIT_HAVE_WINDOW:-0}" = 1 ]; then
      printf ':quit\n' | timeout 120 xvfb-run -a env PATH=/nonexistent "$lcjit" --lab crash.l > out.txt 2> err.txt
      awk '/^step 5 of 5: /{s=NR} /^window open/{w=NR} END{exit !(s && w && s < w)}' out.txt ||
        fail "--lab's window did not open on the model derived to its end: $(cat out.txt)"
    fi ;;
  design)
    mkdir -m 700 "$work/home/.ssh"
    printf 'shape SECRETKEY4711 { SQUARE [] }\n' > "$work/home/.ssh/shapes.cfdg"
    printf 'startshape Tree\nshape Tree\nrule { CIRCLE [] Tree [y 0.8 s 0.8 r 10] }\nrule { SQUARE [] Tree [y 0.8 s 0.8 r -10] }\n' > d.cfdg
    "$lcjit" -b -out free.png --variation ABC d.cfdg > out.txt 2> err.txt || fail "the design does not run without the sandbox"
    "$lcjit" --sandbox -b -out boxed.png --variation ABC d.cfdg > out.txt 2> err.txt; status=$?
    [ "$status" = 0 ] || fail "exit status $status"
    cmp free.png boxed.png || fail "the sandboxed picture differs"
    [ -d .lcjit-cache ] || fail "the sandboxed run kept no cache in the design's folder"
    # A design that imports a file outside its folder: read without the sandbox, not within.
    { printf 'import "%s"\n' "$work/home/.ssh/shapes.cfdg"; cat d.cfdg; } > i.cfdg
    "$lcjit" -b -out i.png i.cfdg > out.txt 2> err.txt || fail "the import does not work without the sandbox"
    rm -f i.png
    "$lcjit" --sandbox -b -out i.png i.cfdg > out.txt 2> err.txt; status=$?
    expect 1 "i.cfdg:1:"
    [ ! -e i.png ] || fail "a picture was written"
    ! grep -q "SECRETKEY" out.txt err.txt || fail "the imported file's text shows"
    # --watch: a saved edit is drawn again, sandboxed.
    "$lcjit" --sandbox --watch -out w.png d.cfdg > out.txt 2> err.txt &
    pid=$!
    for _ in $(seq 1 2400); do [ -s w.png ] && break; sleep 0.05; done
    [ -s w.png ] || fail "no first picture under --watch"
    sed 's/r 10/r 30/' d.cfdg > tmp.cfdg && mv tmp.cfdg d.cfdg
    for _ in $(seq 1 2400); do grep -q "reload 1" err.txt && break; sleep 0.05; done
    grep -q "reload 1 (d.cfdg)" err.txt || fail "no reload after the save" ;;
  profile)
    # --profile alone: the sandboxed run prints the table, the counts of profiled.l (worked out
    # by hand in its header) as without the sandbox; a profile file is refused, none written.
    cp "$dir/../models/profiled.l" .
    "$lcjit" --sandbox -b -out m.obj profiled.l --profile > out.txt 2> err.txt; status=$?
    [ "$status" = 0 ] || fail "exit status $status"
    for want in "production A(n) profiled.l:9 2 2" "production B profiled.l:10 1 1" "decomposition C profiled.l:12 2 2" \
                "interpretation B profiled.l:14 3 3"; do
      awk 'NF == 6 { print $1, $2, $3, $4, $5 }' out.txt | grep -qxF "$want" || fail "no table line $want"
    done
    "$lcjit" --sandbox -b -out m.obj --profile p.json profiled.l > out.txt 2> err.txt; status=$?
    expect 1 "lcjit: --sandbox's runs write one -out file: --profile alone prints the profile as a table"
    [ ! -e p.json ] || fail "a profile file was written" ;;
  *) echo "unknown case $case"; exit 1 ;;
esac
echo "ok: $case"
