#!/usr/bin/env bash
# Bad Context Free designs: for each NAME.cfdg in the folder given, `lcjit cfdg NAME.cfdg` must
# exit with status 1 (no crash) and print every line of NAME.err, which names the place in the
# design (NAME.cfdg:LINE:COL: error: …) in Context Free's terms.
# Usage: run_errors.sh LCJIT DIR
lcjit=$1
dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
for design in "$dir"/*.cfdg; do
  name=$(basename "$design" .cfdg)
  (cd "$dir" && "$lcjit" cfdg "$name.cfdg" "$work/out.svg") >"$work/stdout" 2>"$work/stderr"
  rc=$?
  if [ "$rc" -ne 1 ]; then
    echo "FAIL $name: exit status $rc, expected 1"; cat "$work/stderr"; fail=1; continue
  fi
  while IFS= read -r want || [ -n "$want" ]; do
    [ -z "$want" ] && continue
    if ! grep -qF -- "$want" "$work/stderr"; then
      echo "FAIL $name: stderr lacks: $want"; cat "$work/stderr"; fail=1
    fi
  done <"$dir/$name.err"
  [ -e "$work/out.svg" ] && { echo "FAIL $name: a picture was written"; fail=1; }
  echo "ok $name"
done
exit $fail
