#!/usr/bin/env bash
# Runs lcjit on one bad input and checks that it fails cleanly: exit status 1 (not a signal, not
# a crash), and every line of NAME.err appears (as a substring) in its standard error, except
# lines '! TEXT': TEXT must not appear.
# Usage: run_error.sh LCJIT ERRORS_DIR NAME
# lcjit runs in ERRORS_DIR on `[files from NAME.files] NAME.l`, so messages name the files as
# they are written here (NAME.l:LINE:COL: error: ...). NAME.l need not exist.
extra_prefix=""
source "$(dirname "$0")/model_env.sh"
(cd "$dir" && "$lcjit" -b -out "$work/out.str" "${extra[@]}" "$name.l") >"$work/stdout" 2>"$work/stderr"
rc=$?
echo "--- lcjit exited with $rc; stderr:"
cat "$work/stderr"
fail=0
if [ "$rc" -ne 1 ]; then
  echo "FAIL: expected exit status 1, got $rc"
  fail=1
fi
if grep -qE 'PLEASE submit a bug report|Stack dump|Assertion .* failed|internal error' "$work/stderr"; then
  echo "FAIL: lcjit crashed or reported an internal error"
  fail=1
fi
while IFS= read -r want || [ -n "$want" ]; do
  [ -z "$want" ] && continue
  if [ "${want:0:2}" = "! " ]; then  # "! TEXT": TEXT must not appear (a second error, a generated name)
    if grep -qF -- "${want:2}" "$work/stderr"; then
      echo "FAIL: stderr has what it must not: ${want:2}"
      fail=1
    fi
    continue
  fi
  if ! grep -qF -- "$want" "$work/stderr"; then
    echo "FAIL: stderr lacks: $want"
    fail=1
  fi
done <"$dir/$name.err"
if [ -e "$work/out.str" ]; then
  echo "FAIL: an output string was written although the model is in error"
  fail=1
fi
[ "$fail" -eq 0 ] && echo "ok: $name"
exit "$fail"
