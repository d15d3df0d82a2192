#!/usr/bin/env bash
# Times the light-scaling scene (make_light_scaling_scene.py) at 64, 256, 1024 and 4096
# lights, 1280x720, 4x MSAA: Chiaro's frame and CPU prepare (wall and thread clock), and
# Bevy's frame in the same run when BEVY_BENCH names the peer's binary
# (../shared/peers/bevy-bench). Only ratios measured in one run compare.
#
#   scripts/bench_light_scaling.sh [CHIARO_BINARY]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
chiaro="${1:-$here/../target/release/chiaro}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
printf '%6s %10s %12s %14s %10s\n' lights frame_ms prepare_ms thread_ms bevy_ms
for n in 64 256 1024 4096; do
  scene="$work/lights-$n.gltf"
  python3 "$here/make_light_scaling_scene.py" "$scene" --lights "$n"
  read -r frame prepare thread < <("$chiaro" bench "$scene" --frames 5 --warmup 2 --json 2>/dev/null | python3 -c '
import json, sys
d = json.load(sys.stdin)
print("%.1f %.2f %s" % (d["frame_ms"], d["cpu_prepare_ms"], d.get("cpu_prepare_thread_ms")))')
  bevy="-"
  if [ -n "${BEVY_BENCH:-}" ]; then
    bevy="$("$BEVY_BENCH" "$scene" 1280 720 3 5 2>&1 | sed -n 's/.*median \([0-9.]*\) ms.*/\1/p')"
  fi
  printf '%6s %10s %12s %14.4s %10s\n' "$n" "$frame" "$prepare" "$thread" "$bevy"
done
