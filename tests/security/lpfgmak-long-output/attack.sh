# A model folder's lpfg.mak whose `make -n` prints a command line of 40 MB (a $(shell …) makes
# it; a real one prints some KB). lcjit must read that with a bounded memory and end in an error
# naming lpfg.mak, not grow twenty times the output and abort, and leave no scratch folder.
source "$(dirname "$0")/lib.sh"
command -v make >/dev/null || { echo "skipped: no make"; exit 77; }
cp "$here/model.l" .
size=40000000
printf 'X := $(shell yes | head -c %d)\nlsys.so: lsys.o\n\tg++ -shared -o lsys.so lsys.o $(X)\nlsys.o: lsys.ii\n\tg++ -c lsys.ii\n' \
  $size > lpfg.mak
export LCJIT_CACHE_DIR=$PWD/cache
# /usr/bin/time's %M is the largest of lcjit and the children it waited for: make itself holds
# the line (several times its size), which is make's cost, not lcjit's. The bound is the larger
# of lcjit without the makefile and make alone, and 100 MB for what lcjit may keep of the output.
peak() { /usr/bin/time -f %M -o rss.txt "$@"; local s=$?; rss=$(tail -1 rss.txt); return $s; }
mv lpfg.mak lpfg.mak.off
peak "$lcjit" -b -out o.str model.l > out.txt 2> err.txt || fail "the model does not run without lpfg.mak"
plain=$rss
mkdir alone && echo > alone/lsys.ii && cp lpfg.mak.off alone/lpfg.mak
peak make -n -B -s -C alone -f lpfg.mak lsys.so > /dev/null 2>&1 || fail "make cannot read the makefile"
makes=$rss
mv lpfg.mak.off lpfg.mak
bound=$(( (plain > makes ? plain : makes) + 100 * 1024 ))
# An address-space bound, so that a broken lcjit fails without taking the machine's memory;
# TMPDIR, where lcjit makes its scratch folder, of its own, so that what it leaves shows.
mkdir tmp
TMPDIR=$PWD/tmp peak prlimit --as=3000000000 "$lcjit" -b -out o.str model.l > out.txt 2> err.txt; status=$?
[ $status -ge 128 ] && fail "lcjit was killed by signal $((status - 128)) (exit $status)"
[ $status = 1 ] || fail "exit status $status, not 1 (an error)"
head -1 err.txt | grep -q "lpfg\.mak: error: make -n printed a command line longer than lcjit reads" || fail "the error does not name lpfg.mak and what it printed"
[ "$rss" -le "$bound" ] || fail "peak resident size $((rss / 1024)) MB, over $((bound / 1024)) MB (lcjit alone $((plain / 1024)) MB, make alone $((makes / 1024)) MB)"
left=$(ls tmp | grep lcjit-lpfgmak)
[ -z "$left" ] || fail "left in TMPDIR: $left"
pass "a $((size / 1000000)) MB command line: $(head -1 err.txt | sed 's/.*error: //' | cut -c1-60)…, peak $((rss / 1024)) MB (bound $((bound / 1024)) MB), nothing left in TMPDIR"
