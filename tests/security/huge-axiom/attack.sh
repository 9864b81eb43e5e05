# An axiom of a million modules (a 10 MB model, as a script writes one): compiled as one function
# of calls, its code generation grew faster than its length (128,000 modules: 15 s) and a million
# never finished. The axiom must be compiled as data: the same code whatever its length (a table
# read by a loop), and run to the right string. Then a large axiom of plain numbers and
# expressions with side effects, mixed: every module in its place, every expression evaluated in
# the axiom's order. The models are written here; the expected strings are worked out by awk.
source "$(dirname "$0")/lib.sh"
export LCJIT_CACHE_DIR=$PWD/cache  # a fresh cache: a compiled object found there would prove nothing
# lcjit with a bound on its memory, and on its time for a machine that is broken, not busy.
run() { timeout 250 prlimit --as=4000000000 "$lcjit" "$@"; }

# axiom_model N FILE: `module A(int);` and an axiom of A(0) A(1) … A(N-1), 100 modules a line.
axiom_model() {
  awk -v n="$1" 'BEGIN {
    print "#include <lpfgall.h>\nmodule A(int);\nderivation length: 1;"
    printf "axiom:"
    for (i = 0; i < n; ++i) printf " A(%d)%s", i, (i % 100 == 99 ? "\n" : "")
    print ";"
  }' > "$2"
}

# The compiled axiom is one loop over a table, whatever its length: the C++ holds one call of A's
# writer for 32,000 modules and for 128,000 (a call per module made its code generation grow
# faster than the axiom), and four times the modules are about four times the C++.
axiom_model 32000 small.l
axiom_model 128000 large.l
run --emit-cpp small.l > small.cpp 2> err.txt || fail "--emit-cpp of 32,000 modules failed"
run --emit-cpp large.l > large.cpp 2> err.txt || fail "--emit-cpp of 128,000 modules failed"
for f in small large; do
  calls=$(grep -o '__lc_emit_A(__lc_ctx' $f.cpp | wc -l)
  [ "$calls" -le 2 ] || fail "$f.l: the C++ makes $calls calls of A's writer (the axiom as code, not as a table)"
done
s=$(stat -c %s small.cpp) l=$(stat -c %s large.cpp)
[ $((l * 10)) -le $((s * 45)) ] || fail "4 times the modules gave $l bytes of C++ for $s: more than 4.5 times"

# A million modules, 9.9 MB: compiled and run to the string A(0) … A(999999), one module a line.
axiom_model 1000000 million.l
run -b -out million.str million.l > out.txt 2> err.txt; status=$?
[ $status = 124 ] && fail "a million modules did not compile and run in 250 s"
[ $status = 0 ] || fail "a million modules: exit status $status"
awk 'BEGIN { for (i = 0; i < 1000000; ++i) printf "A(%d)\n", i }' > million.want
[ "$(wc -l < million.str)" = 1000000 ] || fail "the string has $(wc -l < million.str) modules, not 1,000,000"
[ "$(head -1 million.str)" = "A(0)" ] && [ "$(tail -1 million.str)" = "A(999999)" ] || fail "first $(head -1 million.str), last $(tail -1 million.str)"
cmp -s million.str million.want || fail "the string is not A(0) … A(999999): $(cmp million.str million.want)"

# 100,000 modules: A(i) as plain numbers, and A(-next()) (a call with a side effect) for every
# fifth module and for all of 50,000 … 52,999 (runs of calls longer than one compiled function).
awk 'BEGIN {
  print "#include <lpfgall.h>\nmodule A(int), B;\nint calls = 0;\nint next() { return ++calls; }\nderivation length: 1;"
  printf "axiom:"
  for (i = 0; i < 100000; ++i) {
    if (i % 5 == 2 || (i >= 50000 && i < 53000)) printf " A(-next())"; else printf " A(%d)", i
    if (i % 1000 == 999) printf " B\n"
  }
  print ";"
}' > mixed.l
awk 'BEGIN {
  for (i = 0; i < 100000; ++i) {
    if (i % 5 == 2 || (i >= 50000 && i < 53000)) printf "A(%d)\n", -(++calls); else printf "A(%d)\n", i
    if (i % 1000 == 999) print "B"
  }
}' > mixed.want
run -b -out mixed.str mixed.l > out.txt 2> err.txt || fail "the mixed axiom: exit status $?"
cmp -s mixed.str mixed.want || fail "the mixed axiom's string differs from the axiom: $(cmp mixed.str mixed.want)"
pass "a million modules ran to A(0) … A(999999); the axiom's C++ is one loop at 32,000 and 128,000 modules ($s, $l bytes); the mixed axiom kept its order"
