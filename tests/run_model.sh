#!/usr/bin/env bash
# Runs one corpus model in batch mode and compares the final string with NAME.expected.
# Usage: run_model.sh LCJIT MODELS_DIR NAME
set -u
lcjit=$1 dir=$2 name=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
extra=()
if [ -f "$dir/$name.files" ]; then
  for f in $(cat "$dir/$name.files"); do extra+=("$dir/$f"); done
fi
if ! (cd "$work" && "$lcjit" -b -out "$work/out.str" "${extra[@]}" "$dir/$name.l"); then
  echo "FAIL: lcjit exited with an error"
  exit 1
fi
if ! diff -u "$dir/$name.expected" "$work/out.str"; then
  echo "FAIL: the final string differs from $name.expected"
  exit 1
fi
echo "ok: $name"
