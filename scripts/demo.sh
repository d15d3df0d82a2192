#!/usr/bin/env bash
# Installs what is missing, builds Chiaro, and renders the built-in demo scene to chiaro.png.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh
cargo run --release -p chiaro -- render "$@"
