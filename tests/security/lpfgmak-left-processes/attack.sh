# A model folder's lpfg.mak with a $(shell …) that never ends (make runs $(shell …) even with
# -n). When lcjit gives up on make at its time limit, or is ended by SIGTERM or Ctrl-C while
# make runs, nothing the make step started may be left running, nor its scratch folder.
# LCJIT_MAKE_TIME_LIMIT (seconds; 30 by default) shortens the limit so that the test need not wait.
source "$(dirname "$0")/lib.sh"
command -v make >/dev/null || { echo "skipped: no make"; exit 77; }
cp "$here/model.l" .
export LCJIT_CACHE_DIR=$PWD/cache
mkdir tmp && export TMPDIR=$PWD/tmp  # where lcjit makes its scratch folder: what it leaves shows
# The shell make starts writes its pid into FILE, then becomes a sleep that outlives any test.
makefile() {
  printf 'X := $(shell echo $$$$ > %s; exec sleep 86400)\nlsys.so: lsys.o\n\tg++ -shared -o lsys.so lsys.o\nlsys.o: lsys.ii\n\tg++ -c lsys.ii\n' \
    "$PWD/$1" > lpfg.mak
  rm -f "$1"
}
# gone PID: that sleep is not running (a zombie has no command line).
gone() { ! grep -qa 86400 "/proc/$1/cmdline" 2>/dev/null; }
# nothing_left FILE HOW: the sleep whose pid is in FILE ends (at once, or wait_for's bound is hit:
# it is then killed here), and no scratch folder is left.
nothing_left() {
  local pid
  pid=$(cat "$1")
  if ! wait_for 60 gone "$pid"; then
    local what
    what=$(ps -o pid=,ppid=,args= -p "$pid")
    kill "$pid"
    fail "$2: make's \$(shell …) is still running: $what"
  fi
  [ -z "$(ls tmp)" ] || fail "$2: left in TMPDIR: $(ls tmp)"
}
# Whatever happens, no sleep of this test outlives it.
kill_left() {
  local f
  for f in *.pid; do [ -s "$f" ] && ! gone "$(cat "$f")" && kill "$(cat "$f")"; done
}
trap kill_left EXIT

# 1. The time limit. Should make not have started the shell within it (a very busy machine),
# the limit is raised and the run tried again.
makefile limit.pid
limit=2
while :; do
  LCJIT_MAKE_TIME_LIMIT=$limit timeout 600 "$lcjit" -b -out o.str model.l > out.txt 2> err.txt; status=$?
  [ -s limit.pid ] && break
  limit=$((limit * 4))
  [ $limit -gt 200 ] && fail "make never started the \$(shell …)"
done
nothing_left limit.pid "time limit"
[ $status = 1 ] || fail "time limit: exit status $status, not 1"
grep -q "lpfg\.mak: error: make -n did not finish within $limit s" err.txt || fail "time limit: the error does not say so"

# 2. SIGTERM while make runs.
makefile term.pid
LCJIT_MAKE_TIME_LIMIT=3600 "$lcjit" -b -out o.str model.l > out.txt 2> err.txt &
pid=$!
wait_for 300 test -s term.pid || { kill $pid; fail "SIGTERM: make never started the \$(shell …)"; }
kill -TERM $pid
wait $pid
nothing_left term.pid "SIGTERM"

# 3. Ctrl-C while make runs: SIGINT as a terminal sends it (a background job of this script
# would ignore it: env resets it to the default).
if env --default-signal=INT true 2>/dev/null; then
  makefile int.pid
  LCJIT_MAKE_TIME_LIMIT=3600 env --default-signal=INT "$lcjit" -b -out o.str model.l > out.txt 2> err.txt &
  pid=$!
  wait_for 300 test -s int.pid || { kill $pid; fail "Ctrl-C: make never started the \$(shell …)"; }
  kill -INT $pid
  wait $pid
  nothing_left int.pid "Ctrl-C"
  tried="the time limit ($limit s), SIGTERM and Ctrl-C"
else
  tried="the time limit ($limit s) and SIGTERM (this env cannot reset SIGINT: Ctrl-C not tried)"
fi
pass "after $tried, nothing of make's was left running and no scratch folder"
