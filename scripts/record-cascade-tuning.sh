#!/bin/bash
# Records docs/viewer/cascade-split-*.png: the viewer on the demo scene with the cascade
# debug view while the first cascade split is dragged in the panel, as a user tunes it.
# Needs Xvfb, xdotool, xwd (x11-apps) and netpbm; positions fit a 760x560 view.
set -euo pipefail
cd "$(dirname "$0")/.."
out=docs/viewer
mkdir -p "$out"
cargo build --release -p chiaro
display=:79
Xvfb $display -screen 0 1200x700x24 >/dev/null 2>&1 &
xvfb=$!
trap 'kill $viewer $xvfb 2>/dev/null || true' EXIT
sleep 1
export DISPLAY=$display
target/release/chiaro view --debug cascades --width 760 --height 560 >/dev/null 2>&1 &
viewer=$!
sleep 10
# Scroll the panel to the [shadows.directional] section.
xdotool mousemove 950 300
for _ in $(seq 1 10); do xdotool click 5; sleep 0.15; done
sleep 2
capture() {
  sleep 2
  xwd -root -silent | xwdtopnm 2>/dev/null | pnmcut 0 0 1100 560 | pnmscale 0.6 | pnmtopng > "$out/cascade-split-$1.png"
}
capture 1
# The "cascade 1 ends at" slider's handle, dragged left and then right.
xdotool mousemove 832 233 mousedown 1
sleep 0.3; xdotool mousemove 824 233; sleep 0.3; xdotool mousemove 815 233
capture 2
sleep 0.3; xdotool mousemove 830 233; sleep 0.3; xdotool mousemove 839 233
capture 3
sleep 0.3; xdotool mousemove 844 233; sleep 0.3; xdotool mousemove 847 233
capture 4
xdotool mouseup 1
echo "wrote $out/cascade-split-{1,2,3,4}.png"
