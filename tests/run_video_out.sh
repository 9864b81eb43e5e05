#!/usr/bin/env bash
# -out movie.mp4 / movie.webm: a batch run writes the axiom and every step as one video
# frame each, the same frames `-out frame%04d.png` writes as numbered pictures; --fps sets the
# rate. An unwritable place or a --record name that is neither a video nor numbered is an error
# with status 1 that names it.
# Usage: run_video_out.sh LCJIT VIDEO_PROBE IMAGE_DIFF MODEL.l (tests/models/numbered.l: step K
# draws K segments)
set -u
lcjit=$(realpath "$1") probe=$(realpath "$2") diff=$(realpath "$3") model=$(realpath "$4")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
fail() { echo "FAIL: $*"; cat err.txt 2>/dev/null; exit 1; }
cp "$model" numbered.l
# lpfg's rule: the axiom, then one picture per derivation step.
steps=$(sed -n 's/^derivation length: *\([0-9]*\);.*/\1/p' numbered.l)
[ -n "$steps" ] || fail "no derivation length in the model"
frames=$((steps + 1))

"$lcjit" -b -w 320 240 -out 'f%04d.png' numbered.l 2>err.txt || fail "lcjit -out f%04d.png failed"
for video in v.mp4 v.webm; do
  "$lcjit" -b -w 320 240 -out "$video" numbered.l 2>err.txt || fail "lcjit -out $video failed"
  read -r codec w h fps n < <("$probe" "$video" "${video%.*}_") || fail "$video is not a readable video"
  case "$video" in
  *.mp4) [[ "$codec" = h264 || "$codec" = mpeg4 ]] || fail "$video: codec $codec" ;;
  *.webm) [[ "$codec" = vp9 || "$codec" = vp8 ]] || fail "$video: codec $codec" ;;
  esac
  [ "$w $h" = "320 240" ] || fail "$video is ${w}x$h, not 320x240"
  [ "$fps" = 25 ] || fail "$video: $fps frames per second, not the default 25"
  [ "$n" = "$frames" ] || fail "$video has $n frames, not $frames ($steps steps and the axiom)"
  # Frame K is step K's picture: the numbered picture of the same run, up to the codec's loss
  # (none at image_diff's threshold here), and not step K-1's (steps differ by some 40 pixels).
  for ((k = 0; k < frames; k++)); do
    p=$(printf '%04d' $k) q=$(printf '%04d' $((k - 1)))
    "$diff" "f$p.png" "${video%.*}_$p.png" --max-fraction 0.0002 >/dev/null ||
      fail "$video frame $k differs from f$p.png"
    [ $k = 0 ] || ! "$diff" "f$q.png" "${video%.*}_$p.png" --max-fraction 0.0002 >/dev/null ||
      fail "$video frame $k is like f$q.png: the comparison cannot tell steps apart"
  done
done

"$lcjit" -b -w 320 240 --fps 10 -out ten.mp4 numbered.l 2>err.txt || fail "--fps 10 failed"
read -r _ _ _ fps _ < <("$probe" ten.mp4)
[ "$fps" = 10 ] || fail "--fps 10 gave $fps"

# An odd size is padded to the next even one (yuv420p).
"$lcjit" -b -w 321 241 -out odd.mp4 numbered.l 2>err.txt || fail "an odd size failed"
read -r _ w h _ _ < <("$probe" odd.mp4)
[ "$w $h" = "322 242" ] || fail "odd.mp4 is ${w}x$h, not 322x242"

# Errors: status 1 and a message naming the file and the reason; nothing derived in vain.
"$lcjit" -b -out no/such/folder/v.mp4 numbered.l 2>err.txt && fail "an unwritable video succeeded"
grep -q "cannot write no/such/folder/v.mp4: cannot create the file: No such file or directory" err.txt ||
  fail "no message naming the unwritable video"
"$lcjit" -b --record v.avi numbered.l 2>err.txt && fail "--record v.avi succeeded"
grep -q -- "--record v.avi: frames go to a video (.mp4, .webm) or to numbered files" err.txt ||
  fail "no message naming the bad --record name"
"$lcjit" -b --fps 0 -out v.mp4 numbered.l 2>err.txt && fail "--fps 0 succeeded"
echo ok
