# `lcjit repl` driven through a pipe, as a script, an editor or a notebook kernel drives it (a
# kernel's Interrupt is a SIGINT): SIGINT must stop what runs — typed C++ in an endless loop, the
# initializer of a typed global that never returns, a :run of a derivation without end — and the
# session must go on, answering the next input; a SIGINT while nothing runs must not end it
# either. Each SIGINT is sent once the code it is for has said that it runs; nothing waits for a
# fixed time.
source "$(dirname "$0")/lib.sh"
cp "$here/endless.l" .
export LCJIT_CACHE_DIR=$PWD/cache
mkfifo input
# Job control: a job started with `&` by a script without it would have SIGINT ignored, and a
# notebook's or an editor's REPL has it as a program has by default.
set -m
"$lcjit" repl endless.l < input > out.txt 2> err.txt &
pid=$!
exec 3> input
trap '[ -n "$pid" ] && kill -KILL $pid 2>/dev/null' EXIT
send() { printf '%s\n' "$*" >&3; }
# ended: lcjit has exited (a zombie until `wait`).
ended() { [ ! -e /proc/$pid ] || [ "$(cut -d' ' -f3 /proc/$pid/stat 2>/dev/null)" = Z ]; }
# seen FILE PATTERN [N]: at least N (1) lines of FILE match the grep pattern.
seen() { [ "$(grep -c -- "$2" "$1")" -ge "${3:-1}" ]; }
# expect WHAT FILE PATTERN [N]: waits for seen, or fails saying WHAT did not happen.
expect() {
  local what=$1; shift
  wait_for 120 seen_or_ended "$@"
  seen "$@" && return 0
  ended && fail "lcjit ended: $what did not happen"
  fail "$what did not happen"
}
seen_or_ended() { seen "$@" || ended; }

expect "the model's load" out.txt '^step 0 of 2000000000'
kill -INT $pid  # nothing runs: a notebook's Interrupt of an idle kernel
send 'bonus * 11'
expect "an answer after a SIGINT with nothing running" out.txt '^11$'

send 'std::printf("looping\n"); std::fflush(stdout); for (;;) {}'
expect "the typed loop's start" out.txt '^looping$'
kill -INT $pid
expect "the report of the interrupted loop" err.txt '^<repl>: error: interrupted$'
send 'bonus * 12'
expect "an answer after the interrupted loop" out.txt '^12$'

# A global whose initializer never returns: stopped, and not run again as another kind of input.
send 'int stuck = [] { std::printf("initializing\n"); std::fflush(stdout); for (;;) {} return 0; }();'
expect "the typed initializer's start" out.txt '^initializing$'
kill -INT $pid
expect "the report of the interrupted initializer" err.txt 'static constructor or destructor was stopped: interrupted'
send 'bonus * 13'
expect "an answer after the interrupted initializer" out.txt '^13$'
[ "$(grep -c '^initializing$' out.txt)" = 1 ] || fail "the interrupted initializer ran again"

# Between steps the derivation stops quietly ("interrupted"); inside one, a step that does not
# come back is a fault that names it ("... was interrupted in step N"): either is the interrupt.
send ':run'
expect "the derivation's start" out.txt '^deriving$'
kill -INT $pid
run_interrupted() { seen out.txt '^interrupted$' || seen err.txt 'was interrupted in step'; }
wait_for 120 run_interrupted || fail "the report of the interrupted :run did not come"
send 'bonus * 14'
expect "an answer after the interrupted :run" out.txt '^14$'

kill -INT $pid
send ':quit'
exec 3>&-
wait_for 120 ended || fail "lcjit did not end after :quit"
wait $pid
status=$?
pid=
[ $status -lt 128 ] || fail "lcjit was ended by signal $((status - 128))"
[ $status = 1 ] || fail "exit status $status, not 1 (the interrupted inputs are errors of the script)"
pass "three SIGINTs stopped what ran (a typed loop, a typed global's initializer, a :run) and two found nothing running; the session answered after each and ended at :quit"
