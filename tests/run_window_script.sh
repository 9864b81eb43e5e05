#!/usr/bin/env bash
# Drives the lcjit window under Xvfb with xdotool: copies DIR/NAME.* to a scratch folder and runs
# DIR/NAME.drive there (bash) inside the X server, with helpers: start ARGS… (lcjit in the
# background), wait_file F (up to 10 s), wait_window MODEL.l (its window is up), item_centre,
# click_item, wait_item and key_until (below), expect_files GLOB NAMES… (exactly those files),
# fail MSG.
# The script passes by reaching its end; a failure prints lcjit's stderr.
# Usage: run_window_script.sh LCJIT DIR NAME
set -u
lcjit=$1 dir=$2 name=$3
work=$(mktemp -d)
trap 'kill -- -$pid 2>/dev/null; rm -rf "$work"' EXIT
cp "$dir/$name".* "$work/"
cd "$work"
for tool in xvfb-run xdotool; do command -v $tool >/dev/null || { echo "$tool is missing"; exit 1; }; done
cat > helpers.sh <<EOS
start() { "$lcjit" "\$@" > out.txt 2> err.txt & }
fail() { echo "FAIL: \$*"; cat err.txt; [ -f layout.txt ] && { echo "the window's last layout:"; cat layout.txt; }; echo "files: \$(ls | tr '\\n' ' ')"; exit 1; }
wait_file() { for _ in \$(seq 1 600); do [ -f "\$1" ] && return 0; sleep 0.1; done; fail "no \$1"; }
# The window of MODEL.l is up (a slow start on a loaded machine must not lose the first clicks).
wait_window() { timeout 60 xdotool search --sync --onlyvisible --name "lcjit: \$1" >/dev/null || fail "no window for \$1"; }
# With LCJIT_WINDOW_LAYOUT=layout.txt exported before start: item_centre LABEL prints the centre
# ("X Y") of the menu item or panel control (TITLE/LABEL) where the window last drew it, waiting up
# to 60 s for it to be drawn and usable (not greyed out: a busy window greys some items); click_item
# LABEL [right] clicks there (or 3 px inside its right end: a slider's maximum).
item_rect() { awk -F'\t' -v l="\$1" '\$1 == l && \$3 != "greyed" { print \$2 }' layout.txt 2>/dev/null; }
item_centre() {
  for _ in \$(seq 1 600); do [ -n "\$(item_rect "\$1")" ] && break; sleep 0.1; done
  read -r x0 y0 x1 y1 < <(item_rect "\$1")
  [ -n "\$x1" ] || fail "no usable \$1 in the window's layout: \$(cat layout.txt 2>/dev/null)"
  [ "\${2:-}" = right ] && echo \$((x1 - 3)) \$(((y0 + y1) / 2)) || echo \$(((x0 + x1) / 2)) \$(((y0 + y1) / 2))
}
click_item() {
  local at; at=\$(item_centre "\$@") || { echo "\$at"; exit 1; }
  xdotool mousemove \$at click 1
}
# wait_item LABEL: waits up to 60 s until the window's layout lists LABEL (its start: a panel's
# text lines are listed by their text).
wait_item() {
  for _ in \$(seq 1 600); do grep -qF "\$1" layout.txt 2>/dev/null && return 0; sleep 0.1; done
  fail "no \$1 in the window's layout: \$(cat layout.txt 2>/dev/null)"
}
# key_until FILE KEY: presses KEY (xdotool key) until FILE exists, giving each press 2 s. For
# keys the window drops while it is busy (Ctrl+F during a step): FILE must appear before the
# window takes the next press (written by the step, or by the frame that shows it), so a press
# repeated while the last one is still at work is dropped, never taken twice.
key_until() {
  for _ in \$(seq 1 20); do
    xdotool key "\$2"
    for _ in \$(seq 1 20); do [ -f "\$1" ] && return 0; sleep 0.1; done
  done
  fail "no \$1 after pressing \$2 twenty times"
}
expect_files() {  # expect_files GLOB NAMES…
  local have want; have=\$(ls \$1 2>/dev/null | tr '\n' ' '); shift; want="\$* "
  [ "\$have" = "\$want" ] || fail "expected files: \$want; have: \$have"
}
EOS
setsid xvfb-run -a -s "-screen 0 1024x768x24" bash -c ". ./helpers.sh; . ./$name.drive && echo ok > passed" > log.txt 2>&1 &
pid=$!
wait $pid
cat log.txt
[ -f passed ] || exit 1
echo "ok: $name"
