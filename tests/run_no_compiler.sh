#!/usr/bin/env bash
# lcjit compiles in-process: no compiler (or any other) process may be started. Runs one corpus
# model (tests/models/NAME.l, compared with NAME.expected) twice:
#   1. under `env -i` (no PATH at all) with a fresh, empty PCH cache, so the runtime header is
#      precompiled in this run too;
#   2. with PATH holding only fake clang/gcc/ld/... that record any call, reusing that cache.
# Where strace works, both runs are traced and must show exactly one execve: lcjit's own.
# Usage: run_no_compiler.sh LCJIT MODELS_DIR NAME
source "$(dirname "$0")/model_env.sh"
fail=0

fake="$work/fakebin"
mkdir -p "$fake"
for tool in cc c++ gcc g++ clang clang++ clang-19 clang++-19 cpp ld ld.lld ld.gold lld as llc opt sh bash; do
  printf '#!/bin/sh\necho "%s $*" >>"%s/called"\nexit 1\n' "$tool" "$work" >"$fake/$tool"
  chmod +x "$fake/$tool"
done

strace=$(command -v strace || true)
if [ -n "$strace" ] && ! "$strace" -f -qq -e trace=execve -o /dev/null true 2>/dev/null; then strace=""; fi
[ -z "$strace" ] && echo "note: strace is not usable here; relying on PATH checks only"

run() {  # run LABEL TRACE ENV... -- executes lcjit in $work/LABEL with the given environment
  local label=$1 trace=$2
  shift 2
  mkdir -p "$work/$label"
  local cmd=("$lcjit" -b -out "$work/$label/out.str" "${extra[@]}" "$dir/$name.l")
  if [ -n "$strace" ]; then cmd=("$strace" -f -qq -e trace=execve -o "$trace" "${cmd[@]}"); fi
  (cd "$work/$label" && env "$@" "${cmd[@]}")
  local rc=$?
  if [ "$rc" -ne 0 ]; then
    echo "FAIL: $label: lcjit exited with $rc"
    fail=1
  elif ! diff -u "$dir/$name.expected" "$work/$label/out.str"; then
    echo "FAIL: $label: the final string differs from $name.expected"
    fail=1
  fi
  if [ -n "$strace" ]; then
    local n
    n=$(grep -c 'execve(' "$trace")
    if [ "$n" -ne 1 ]; then
      echo "FAIL: $label: $n execve calls (expected only lcjit's own):"
      grep 'execve(' "$trace"
      fail=1
    fi
  fi
  if [ -f "$work/called" ]; then
    echo "FAIL: $label: lcjit ran external tools:"
    cat "$work/called"
    fail=1
  fi
}

# 1. No environment at all (env -i: no PATH, no HOME); a fresh cache forces the PCH build.
run empty_env "$work/trace1" -i LCJIT_CACHE_DIR="$work/cache"
if [ -z "$(ls -A "$work/cache" 2>/dev/null)" ]; then
  echo "FAIL: empty_env: no precompiled header was written to the fresh cache"
  fail=1
fi
# 2. PATH with fake compilers only; the cached PCH is reused.
run fake_path "$work/trace2" PATH="$fake" LCJIT_CACHE_DIR="$work/cache"

[ "$fail" -eq 0 ] && echo "ok: $name ran without starting any process"
exit "$fail"
