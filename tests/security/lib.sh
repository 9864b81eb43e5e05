# Sourced by every tests/security/*/attack.sh (see README.md): what the attacks share.
# Sets: lcjit (the binary), here (the attack's folder). The working folder is the current one.
lcjit=${1:?usage: attack.sh LCJIT}
here=$(cd "$(dirname "${BASH_SOURCE[1]}")" && pwd)

# keep PID: a process the attack started in the background, killed when the attack ends however it
# ends (a failed check must not leave a --watch running).
kept=()
keep() { kept+=("$1"); }
trap 'for p in "${kept[@]}"; do kill "$p" 2>/dev/null; done' EXIT

# fail WHAT: the attack succeeded; say what happened, with lcjit's output if there is any.
fail() {
  echo "FAIL: $*"
  for f in out.txt err.txt; do [ -s "$f" ] && { echo "--- $f"; head -c 4000 "$f"; echo; }; done
  exit 1
}
pass() { echo "ok: $*"; exit 0; }

# need_sandbox: skip (77) where bubblewrap cannot make a sandbox (not installed, no user namespaces).
need_sandbox() {
  if ! command -v bwrap >/dev/null || ! bwrap --unshare-all --ro-bind / / true 2>/dev/null; then
    echo "skipped: bubblewrap cannot make a sandbox here"
    exit 77
  fi
}

# wait_for SECONDS COMMAND…: polls COMMAND (every 0.05 s) until it succeeds; 1 if it never did.
# The bound is for a machine that never gets there, not a guess at how long it takes.
wait_for() {
  local limit=$1; shift
  local end=$((SECONDS + limit))
  until "$@"; do
    [ $SECONDS -ge $end ] && return 1
    sleep 0.05
  done
}

# peak_rss_kb PID: the peak resident size (VmHWM) of a running process, in KB; 0 once it is gone.
peak_rss_kb() { awk '/^VmHWM/{print $2; found=1} END{if (!found) print 0}' "/proc/$1/status" 2>/dev/null || echo 0; }

# processes_in DIR: the pids whose working folder is DIR or under it (what a run left behind).
processes_in() {
  local d p
  d=$(cd "$1" && pwd -P)
  for p in /proc/[0-9]*; do
    case "$(readlink "$p/cwd" 2>/dev/null)" in "$d" | "$d"/*) echo "${p#/proc/}" ;; esac
  done
}
