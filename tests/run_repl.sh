#!/usr/bin/env bash
# The REPL end to end (tests/repl/): copies tests/repl to a scratch folder and runs there
#  * NAME.in: `lcjit repl $(cat NAME.args) < NAME.in`, stdout and stderr together, then the line
#    "exit status N"; timings ("1.23 ms") read "N ms". That output must equal NAME.expected when
#    there is one; NAME.check (bash, with the output in out.txt) runs after when there is one.
#  * NAME.drive (bash): a session fed line by line as the script goes, with helpers:
#    start ARGS… (lcjit repl ARGS… in the background; start_lab: lcjit --lab ARGS… without bwrap), send LINE, expect PATTERN [N] (waits up to
#    60 s for N lines (1) of the output to match the grep pattern), finish (ends the input and
#    waits: $status), fail MESSAGE.
# Usage: run_repl.sh LCJIT DIR NAME
set -u
lcjit=$1 dir=$2 name=$3
work=$(mktemp -d)
pid=
trap '[ -n "$pid" ] && kill $pid 2>/dev/null; rm -rf "$work"' EXIT
cp "$dir"/* "$work/"
cd "$work"

fail() {
  echo "FAIL: $name: $*"
  echo "--- output:"
  cat out.txt
  exit 1
}

if [ -f "$name.drive" ]; then
  start() {
    mkfifo input
    "$lcjit" repl "$@" < input > out.txt 2>&1 &
    pid=$!
    exec 3> input
  }
  start_lab() {  # lcjit --lab ARGS…: the REPL with the window and the watcher, which --lab
    mkfifo input  # has only where it cannot sandbox (docs/security.md): bubblewrap hidden
    env PATH=/nonexistent "$lcjit" --lab "$@" < input > out.txt 2>&1 &
    pid=$!
    exec 3> input
  }
  send() { printf '%s\n' "$*" >&3; }
  expect() {
    local want=${2:-1}
    for _ in $(seq 1 600); do
      [ "$(grep -c -- "$1" out.txt)" -ge "$want" ] && return 0
      sleep 0.1
    done
    fail "expected ${want} line(s) matching '$1'"
  }
  finish() {
    exec 3>&-
    wait $pid
    status=$?
    pid=
  }
  . "./$name.drive"
else
  "$lcjit" repl $(cat "$name.args" 2>/dev/null) < "$name.in" > raw.txt 2>&1
  echo "exit status $?" >> raw.txt
  sed -E 's/[0-9]+\.[0-9]+ ms/N ms/g' raw.txt > out.txt
  if [ -f "$name.expected" ]; then
    diff -u "$name.expected" out.txt || fail "the output differs from $name.expected"
  fi
  if [ -f "$name.check" ]; then
    bash -e "$name.check" || fail "$name.check failed"
  fi
fi
echo "ok: $name"
