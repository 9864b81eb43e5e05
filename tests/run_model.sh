#!/usr/bin/env bash
# Runs one corpus model in batch mode and compares the final string with NAME.expected.
# Usage: run_model.sh LCJIT MODELS_DIR NAME [LCJIT OPTIONS...]
source "$(dirname "$0")/model_env.sh"
options=("${@:4}")
if ! (cd "$work" && "$lcjit" -b "${options[@]}" -out "$work/out.str" "${extra[@]}" "$dir/$name.l"); then
  echo "FAIL: lcjit exited with an error"
  exit 1
fi
if ! diff -u "$dir/$name.expected" "$work/out.str"; then
  echo "FAIL: the final string differs from $name.expected"
  exit 1
fi
echo "ok: $name"
