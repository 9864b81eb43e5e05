# A model's static arrays and --max-memory. The guard watches lcjit's memory only while model code
# runs; a model's arrays are allocated before, when it is linked. So: an array larger than the
# limit must be refused at its declaration, before any of it is allocated; one within the limit
# must stay untouched (zero pages are not resident) until the model writes it, however large; and
# arrays beyond what x86-64 code reaches must be an error in the model's terms (its file, line and
# variable), never the JIT linker's ("lcjit.model.1 ... Delta32"). Every run is under an address
# space limit, so that a regression cannot take the machine's memory.
source "$(dirname "$0")/lib.sh"
cp "$here/grid.l" "$here/voxels.l" "$here/many.l" .
export LCJIT_CACHE_DIR=$PWD/cache

# run MODEL MAX-MEMORY: lcjit -b on MODEL under 8 GB of address space; its peak resident size in
# MB goes to $rss, its exit status to $status.
run() {
  prlimit --as=8000000000 /usr/bin/time -f %M -o rss.txt timeout 300 "$lcjit" -b --max-memory "$2" -out o.str "$1" > out.txt 2> err.txt
  status=$?
  rss=$(( $(tail -1 rss.txt) / 1024 ))
}

# 1 GB under a 300 MB limit: refused where it is declared (line 5, the name at column 13), naming
# the limit; nothing written, and lcjit never near the array's size.
run grid.l 300M
[ $status = 1 ] || fail "grid.l under --max-memory 300M: exit $status, expected 1"
head -1 err.txt | grep -q "^grid\.l:5:13: error: .*1\.00 GB.*--max-memory 300\.00 MB.*'grid'" ||
  fail "grid.l: the error does not name the array's declaration (grid.l:5:13), its size and the limit"
[ -e o.str ] && fail "grid.l: a string was written"
[ $rss -lt 512 ] || fail "grid.l: lcjit reached $rss MB, more than half the array's 1 GB"

# Within the limit, the same model runs, and its array stays zero pages but for the one written.
run grid.l 2G
[ $status = 0 ] || fail "grid.l under --max-memory 2G: exit $status"
grep -q "^A(7)" o.str || fail "grid.l: the string is not A(7)"
[ $rss -lt 512 ] || fail "grid.l: lcjit reached $rss MB for a model that wrote one byte of its 1 GB array"

# 4 GB (more than code reaches, 2 GB) under a 2 GB limit: refused at its declaration (line 6,
# column 14).
rm -f o.str
run voxels.l 2G
[ $status = 1 ] || fail "voxels.l under --max-memory 2G: exit $status, expected 1"
head -1 err.txt | grep -q "^voxels\.l:6:14: error: .*4\.00 GB.*--max-memory 2\.00 GB.*'space'" ||
  fail "voxels.l: the error does not name the array's declaration (voxels.l:6:14), its size and the limit"

# Under a 6 GB limit it runs: the last voxel and the variables on either side of the space are
# written and read back (1 + 3 + 2), and lcjit stays far below the space's size.
run voxels.l 6G
[ $status = 0 ] || fail "voxels.l under --max-memory 6G: exit $status"
grep -q "^A(6)" o.str || fail "voxels.l: the string is not A(6)"
[ $rss -lt 1024 ] || fail "voxels.l: lcjit reached $rss MB for a model that wrote one voxel"
voxelsRss=$rss

# 140 arrays of 15 MB: the link fails, at one of their declarations (lines 7-20), naming it.
rm -f o.str
run many.l 4G
[ $status = 1 ] || fail "many.l: exit $status, expected 1"
place=$(head -1 err.txt | grep -o "^many\.l:[0-9]*:[0-9]*: error: 'a[0-9]*' lies farther from the model's code than x86-64 code reaches")
[ -n "$place" ] || fail "many.l: the error does not name an array and its declaration"
line=$(echo "$place" | cut -d: -f2) column=$(echo "$place" | cut -d: -f3)
[ "$line" -ge 7 ] && [ "$line" -le 20 ] || fail "many.l: line $line is not one of the arrays' (7-20)"
[ "$column" -le "$(sed -n "${line}p" many.l | tr -d '\n' | wc -c)" ] || fail "many.l: column $column is past the end of line $line"
grep -qE "lcjit\.model|Delta32|JIT link" err.txt && fail "many.l: the error speaks of the JIT linker's insides"
pass "arrays over the limit refused at their declaration; a 4 GB array ran in $voxelsRss MB; arrays out of reach named"
