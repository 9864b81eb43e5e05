#!/usr/bin/env bash
# The progress line of a long derivation on a terminal (batch and the REPL): on a terminal (a pty from
# script(1)) lcjit writes "lcjit: step K of N: M modules", rewritten in place, clears it before
# the model's own output and when the derivation ends; LCJIT_PROGRESS_AFTER_MS=0 shows it from the first step (by default a run
# must have gone on for half a second). Not on a pipe or a file, not with -q.
# Usage: run_progress.sh LCJIT MODEL.l (tests/models/progress.l: step K leaves 2^K modules)
set -u
lcjit=$(realpath "$1") model=$(realpath "$2")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
fail() { echo "FAIL: $*"; cat -A tty.txt 2>/dev/null | head -5; exit 1; }
command -v script >/dev/null || { echo "script(1) is missing (bsdutils)"; exit 1; }

LCJIT_PROGRESS_AFTER_MS=0 script -qfec "'$lcjit' -b -out tty.str '$model'" /dev/null > tty.txt || fail "lcjit failed on a terminal"
grep -q $'\rlcjit: step 1 of 8: 2 modules\e\[K' tty.txt || fail "no progress line for step 1"
# Every line shown is right: step K, 2^K modules.
lines=$(tr '\r' '\n' < tty.txt | grep -o 'lcjit: step [0-9]* of 8: [0-9]* modules')
[ -n "$lines" ] || fail "no progress lines"
while read -r _ _ k _ _ m _; do
  [ "$m" = $((1 << ${k})) ] || fail "step $k shows $m modules, not $((1 << k))"
done <<< "$lines"
# The model's own output starts on a line of its own: the progress line is cleared before it.
grep -q $'modules\e\[K\r\e\[Kdone' tty.txt || fail "the model's output does not clear the progress line first"
# Without output of the model's, the line is cleared when the derivation ends: the last thing written.
sed '/EndEach/d' "$model" > silent.l
LCJIT_PROGRESS_AFTER_MS=0 script -qfec "'$lcjit' -b -out silent.str silent.l" /dev/null > silent.txt || fail "lcjit failed"
grep -q 'lcjit: step 1 of 8' silent.txt || fail "no progress line for the silent model"
[ "$(tail -c 4 silent.txt | od -An -c | tr -d ' ')" = '\r033[K' ] || fail "the progress line is not cleared at the end"

# The REPL's :run shows the same line on its terminal.
printf ':load %s\n:run\n' "$(basename "$model")" > commands.txt
cp "$model" .
LCJIT_PROGRESS_AFTER_MS=0 script -qfec "'$lcjit' repl < commands.txt" /dev/null > repl.txt || fail "the REPL failed"
grep -q $'\rlcjit: step 1 of 8: 2 modules\e\[K\r\e\[Kdone' repl.txt || fail "no progress line in the REPL, cleared before the model's output: $(cat -A repl.txt | head -5)"

LCJIT_PROGRESS_AFTER_MS=0 "$lcjit" -b -out file.str "$model" 2> err.txt || fail "lcjit failed"
grep -q 'step' err.txt && fail "a progress line on a file: $(cat -A err.txt)"
LCJIT_PROGRESS_AFTER_MS=0 script -qfec "'$lcjit' -b -q -out quiet.str '$model'" /dev/null > quiet.txt || fail "lcjit -q failed"
grep -q 'step' quiet.txt && fail "a progress line with -q"
cmp -s tty.str file.str && cmp -s tty.str quiet.str || fail "the strings differ"
echo ok
