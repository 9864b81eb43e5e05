#!/usr/bin/env bash
# Builds the fuzz targets (tests/fuzz: clang-19, libFuzzer, ASan, UBSan) in build-fuzz and runs
# them (docs/fuzzing.md). Seeds are the repository's own files (examples/, tests/), copied into
# corpora outside the repository.
#   bench/fuzz.sh SECONDS [TARGET…]  each target for SECONDS; its corpus build-fuzz/corpus/NAME grows
#   bench/fuzz.sh --smoke [TARGET…]  the suite's fuzz.smoke: each target's regression inputs
#                                    (tests/fuzz/regressions/NAME), then a fixed number of runs from
#                                    a few seeds (a count, not a time: the same work on a busy machine)
# Findings (crashes, sanitizer reports, timeouts, out-of-memory) are saved in
# build-fuzz/findings/NAME/ and listed (the log: build-fuzz/findings/NAME.log, NAME.smoke.log);
# the exit status is 1 if there was any.
# Environment: LCJIT_FUZZ_BUILD (default build-fuzz), LCJIT_FUZZ_ARGS (more libFuzzer flags).
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${LCJIT_FUZZ_BUILD:-$root/build-fuzz}

usage() { echo "usage: bench/fuzz.sh SECONDS|--smoke [TARGET…]" >&2; exit 2; }
[ $# -ge 1 ] || usage
mode=$1
shift
if [ "$mode" != --smoke ] && ! [[ "$mode" =~ ^[0-9]+$ ]]; then usage; fi

all=(view animation environment colormap materials contour contour_set surface bspline terrain obj ply image
     func fset tset vset rewriter strb pipeline)
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=("${all[@]}")

# The fuzzers need clang 19 with its sanitizer and libFuzzer runtimes (setup.sh installs both).
if ! command -v clang++-19 >/dev/null || ! command -v clang-19 >/dev/null; then
  echo "fuzz.sh: clang++-19 not found: install clang-19 and libclang-rt-19-dev (setup.sh does)" >&2
  exit 1
fi
if [ ! -f "$(clang++-19 -print-resource-dir)/lib/linux/libclang_rt.fuzzer-x86_64.a" ]; then
  echo "fuzz.sh: clang-19's libFuzzer runtime is missing: install libclang-rt-19-dev (setup.sh does)" >&2
  exit 1
fi

# -O1 with line tables: fast enough to fuzz, stack traces with lines. NDEBUG as in the release
# build (LLVM's headers are built so).
if [ ! -f "$build/build.ninja" ]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_CXX_COMPILER=clang++-19 -DCMAKE_C_COMPILER=clang-19 \
    -DCMAKE_CXX_FLAGS_RELEASE="-O1 -gline-tables-only -DNDEBUG" -DCMAKE_C_FLAGS_RELEASE="-O1 -gline-tables-only -DNDEBUG" \
    -DLCJIT_FUZZ=ON -DLCJIT_WITH_RENDERING=OFF -DLCJIT_WITH_WINDOW=OFF >/dev/null || exit 1
fi
build_targets=()
for t in "${targets[@]}"; do build_targets+=("fuzz_$t"); done
cmake --build "$build" -j2 --target "${build_targets[@]}" || exit 1

# Seeds: the repository's files of the reader's format (tests/fuzz/seeds/NAME: made for it).
seeds() {
  local find_in=("$root/examples" "$root/tests")
  local -a names
  case $1 in
    view) names=(-name '*.v') ;;
    animation) names=(-name '*.a') ;;
    environment) names=(-name '*.e') ;;
    colormap) names=(-name '*.map') ;;
    materials) names=(-name '*.mat') ;;
    contour) names=(-name '*.con') ;;
    contour_set) names=(-name '*.cset') ;;
    surface) names=(-name '*.s' -not -path '*/bsplines/*') ;;
    bspline) names=(-path '*/bsplines/*.s' -o -name 'bspline*.s') ;;
    terrain) names=(-name '*.patch') ;;
    obj) names=(-name '*.obj') ;;
    ply) names=(-name '*.ply') ;;
    image) names=(-name '*.rgb' -o -name '*.jpg' -o -path '*/examples/*.png') ;;
    func) names=(-name '*.func') ;;
    fset) names=(-name '*.fset') ;;
    tset) names=(-name '*.tset') ;;
    vset) names=(-name '*.vset') ;;
    rewriter | pipeline) names=(-name '*.l') ;;
    strb) return ;;  # the target writes its model's own string (LCJIT_FUZZ_STRB_SEED)
  esac
  find "${find_in[@]}" -type f \( "${names[@]}" \) -not -path '*/tests/fuzz/*' | sort
  # Hand-made seeds of what the repository has no file of (binary PLY), then past findings.
  find "$root/tests/fuzz/seeds/$1" "$root/tests/fuzz/regressions/$1" -type f 2>/dev/null | sort
}

# examples/koch.l -> examples_koch.l: files of the same name from different folders all count.
seed_name() { local r=${1#"$root"/}; echo "${r//\//_}"; }

# Per target: libFuzzer's limits and how many runs the smoke test makes. The JIT and Clang keep
# memory on purpose (caches, the loaded model), so per-input leak checks are off where they run.
flags() {
  case $1 in
    pipeline) echo "-timeout=60 -rss_limit_mb=6144 -malloc_limit_mb=4096 -detect_leaks=0 -max_len=4096" ;;
    strb) echo "-timeout=30 -rss_limit_mb=4096 -detect_leaks=0 -max_len=8192" ;;
    rewriter) echo "-timeout=30 -rss_limit_mb=4096 -max_len=8192" ;;
    *) echo "-timeout=20 -rss_limit_mb=4096 -max_len=65536" ;;
  esac
}
# Model code (JIT'd, not instrumented) may leak as it likes: LeakSanitizer's report at exit would be
# the model's, not lcjit's.
asan_options() {
  case $1 in
    pipeline | strb) echo "detect_leaks=0${ASAN_OPTIONS:+:$ASAN_OPTIONS}" ;;
    *) echo "${ASAN_OPTIONS:-}" ;;
  esac
}
smoke_runs() {
  case $1 in
    pipeline) echo 8 ;;
    strb) echo 300 ;;
    rewriter) echo 300 ;;
    *) echo 3000 ;;
  esac
}

failed=()
for t in "${targets[@]}"; do
  bin="$build/tests/fuzz/fuzz_$t"
  findings="$build/findings/$t"
  mkdir -p "$findings"
  work=$(mktemp -d)  # where a target's own files (OutputString and the like) end up
  corpus="$build/corpus/$t"
  regressions=("$root/tests/fuzz/regressions/$t"/*)
  [ -e "${regressions[0]}" ] || regressions=()
  if [ "$mode" = --smoke ]; then
    corpus="$work/corpus"
    mkdir -p "$corpus"
    seeds "$t" | head -n 4 | while read -r f; do cp "$f" "$corpus/$(seed_name "$f")"; done
  else
    mkdir -p "$corpus"
    seeds "$t" | while read -r f; do cp -n "$f" "$corpus/$(seed_name "$f")"; done
  fi
  [ "$t" = strb ] && export LCJIT_FUZZ_STRB_SEED="$corpus/model.strb"
  log="$build/findings/$t.log"
  [ "$mode" = --smoke ] && log="$build/findings/$t.smoke.log"
  : >"$log"
  status=0
  before=$(ls "$findings" | wc -l)
  if [ ${#regressions[@]} -gt 0 ]; then
    # Each regression input once (they must not fail again).
    (cd "$work" && ASAN_OPTIONS=$(asan_options "$t") "$bin" $(flags "$t") -artifact_prefix="$findings/" "${regressions[@]}") \
      >"$log" 2>&1 || status=$?
  fi
  if [ $status -eq 0 ]; then
    if [ "$mode" = --smoke ]; then
      limit="-runs=$(smoke_runs "$t") -seed=1"
    else
      limit="-max_total_time=$mode"
    fi
    # shellcheck disable=SC2086
    (cd "$work" && ASAN_OPTIONS=$(asan_options "$t") "$bin" $(flags "$t") $limit -print_final_stats=1 -artifact_prefix="$findings/" \
       ${LCJIT_FUZZ_ARGS:-} "$corpus") >>"$log" 2>&1 || status=$?
  fi
  unset LCJIT_FUZZ_STRB_SEED
  rm -rf "$work"
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | tail -1 | grep -o '[0-9]*$')
  after=$(ls "$findings" | wc -l)
  if [ $status -ne 0 ] || [ "$after" -gt "$before" ]; then
    echo "fuzz $t: FINDING (exit $status; $log):"
    grep -E '^(==[0-9]+==ERROR|SUMMARY|.*runtime error|lcjit fuzz:|artifact_prefix|Test unit written)' "$log" | head -8 | sed 's/^/  /'
    failed+=("$t")
  else
    echo "fuzz $t: ${runs:-?} runs, no finding"
  fi
done

if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz.sh: findings in: ${failed[*]} (inputs in $build/findings/)" >&2
  exit 1
fi
