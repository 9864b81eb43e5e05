#!/usr/bin/env bash
# Animate mode in the window under Xvfb, driven with xdotool: -a stops at the animation file's
# first frame (steps 1-2 derived, not 3); Ctrl+F (Step) derives one frame of `step: 2` (3-4, not
# 5); Ctrl+R (Run) goes on to the last frame (5). Each step exports step<N>.obj from EndEach.
# Usage: run_animate.sh LCJIT DIR (DIR holds animate.l and animate.a)
set -u
lcjit=$1 dir=$2
work=$(mktemp -d)
trap 'kill -- -$pid 2>/dev/null; rm -rf "$work"' EXIT
cp "$dir/animate.l" "$dir/animate.a" "$work/"
cd "$work"
for tool in xvfb-run xdotool; do command -v $tool >/dev/null || { echo "$tool is missing"; exit 1; }; done
cat > drive.sh <<'EOS'
"$1" -a animate.a animate.l 2> err.txt &
for _ in $(seq 1 100); do [ -f step2.obj ] && break; sleep 0.1; done
sleep 0.5; ls step*.obj > at_first_frame.txt
xdotool mousemove 300 300; sleep 0.2
xdotool keydown ctrl keydown shift click 3 keyup shift keyup ctrl; sleep 0.5
xdotool mousemove 330 318 click 1; sleep 0.5
xdotool mousemove 300 300; sleep 0.2
xdotool keydown shift keydown ctrl click 1 keyup ctrl keyup shift; sleep 0.3
xdotool key ctrl+f
for _ in $(seq 1 50); do [ -f step4.obj ] && break; sleep 0.1; done
sleep 0.5; ls step*.obj > after_step.txt
xdotool key ctrl+r
for _ in $(seq 1 50); do [ -f step5.obj ] && break; sleep 0.1; done
ls step*.obj > after_run.txt
EOS
setsid xvfb-run -a -s "-screen 0 1024x768x24" bash drive.sh "$lcjit" &
pid=$!
wait $pid
expect() {  # expect FILE STEPS...: FILE lists exactly step1.obj … stepN.obj
  want=$(for s in "${@:2}"; do echo "step$s.obj"; done)
  [ "$(cat "$1" 2>/dev/null)" = "$want" ] || { echo "$1: expected $(echo $want), got $(cat "$1" 2>/dev/null | tr '\n' ' ')"; cat err.txt; exit 1; }
}
expect at_first_frame.txt 1 2
expect after_step.txt 1 2 3 4
expect after_run.txt 1 2 3 4 5
[ -f choice7.txt ] || { echo "the user menu choice did not reach UserMenuChoice()"; cat err.txt; exit 1; }
[ -f pushed.txt ] || { echo "GetMouseStatus() did not report the Shift+Ctrl click"; cat err.txt; exit 1; }
echo "ok: first frame 2, Step to 4, Run to 5; user menu choice 7 and a Shift+Ctrl click seen by the model"
