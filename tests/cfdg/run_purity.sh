#!/usr/bin/env bash
# Context Free's parameter requirements and natural numbers (docs/cfdg.md): each NAME.cfdg in the
# folder given says on its first line `# refused at LINE:COL by the number parameter requirement`,
# `… by the natural number requirement`, `# refused at LINE:COL with: MESSAGE` (another of Context
# Free's errors, as it words it), or `# accepted`. Refused: `lcjit cfdg` exits 1, prints
# NAME.cfdg:LINE:COL: error: and Context Free's words, and writes no picture. Accepted: lcjit
# draws it. With cfdg installed, cfdg is held to the same line at test time (it counts columns from
# 0: COL - 1), so the expectations are its.
# Usage: run_purity.sh LCJIT DIR
lcjit=$1
dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
have_cfdg=0
command -v cfdg >/dev/null && have_cfdg=1
fail=0
for design in "$dir"/*.cfdg; do
  name=$(basename "$design" .cfdg)
  first=$(head -1 "$design")
  place=$(printf '%s\n' "$first" | sed -nE 's/^# refused at ([0-9]+:[0-9]+) (by the|with:) .*/\1/p')
  case "$first" in
    "# refused at $place with: "*)
      message=${first#"# refused at $place with: "} ;;
    "# refused at $place by the number parameter requirement"*)
      message="This expression does not satisfy the number parameter requirement" ;;
    "# refused at $place by the natural number requirement"*)
      message="this expression does not satisfy the natural number requirement" ;;
    "# accepted"*) place= ;;
    *) echo "FAIL $name: the first line says neither '# refused at LINE:COL by the … requirement' nor '# accepted'"
       fail=1; continue ;;
  esac
  rm -f "$work/out.svg" "$work/out.png"
  ok=1
  (cd "$dir" && "$lcjit" cfdg "$name.cfdg" "$work/out.svg") >"$work/stdout" 2>"$work/stderr"
  rc=$?
  if [ -n "$place" ]; then
    want="$name.cfdg:$place: error: $message"
    if [ "$rc" -ne 1 ] || ! grep -qF -- "$want" "$work/stderr" || [ -e "$work/out.svg" ]; then
      echo "FAIL $name: lcjit exit status $rc, expected 1 and: $want"; cat "$work/stderr"; ok=0
    fi
  elif [ "$rc" -ne 0 ] || [ ! -s "$work/out.svg" ]; then
    echo "FAIL $name: lcjit exit status $rc, expected a picture"; cat "$work/stderr"; ok=0
  fi
  if [ "$have_cfdg" = 1 ]; then
    (cd "$dir" && cfdg -q -s 50 "$name.cfdg" "$work/out.png") >"$work/cfdg.out" 2>&1
    crc=$?
    if [ -n "$place" ]; then
      line=${place%:*} col=${place#*:}
      want="$name.cfdg:$line:$((col - 1)): error: $message"
      if [ "$crc" -eq 0 ] || ! grep -qF -- "$want" "$work/cfdg.out"; then
        echo "FAIL $name: cfdg exit status $crc, expected: $want"; cat "$work/cfdg.out"; ok=0
      fi
    elif [ "$crc" -ne 0 ]; then
      echo "FAIL $name: cfdg refuses it"; cat "$work/cfdg.out"; ok=0
    fi
  fi
  if [ "$ok" = 1 ]; then echo "ok $name"; else fail=1; fi
done
[ "$have_cfdg" = 1 ] || echo "(cfdg is not installed: lcjit checked against the first lines only)"
exit $fail
