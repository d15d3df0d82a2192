#!/bin/bash
# The viewer's frame time against `chiaro bench`'s on the benchmark scene, interleaved in
# one run (on shared machines only ratios measured together are stable). Each viewer line
# also gives its own GPU time by timestamps. Needs xvfb-run (scripts/setup.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
scene=${1:-tests/assets/chiaro-bench/shadow-bench.gltf}
rounds=${2:-6}
cargo build --release -p chiaro
chiaro=${CARGO_TARGET_DIR:-$PWD/target}/release/chiaro
for i in $(seq 1 "$rounds"); do
  viewer=$(xvfb-run -a -s "-screen 0 1920x1080x24" "$chiaro" view "$scene" --exit-after-frames 40 2>&1 | grep "frames shown")
  bench=$("$chiaro" bench "$scene" --frames 40 --json 2>/dev/null)
  echo "round $i: ${viewer#chiaro: } | bench: $bench"
done
