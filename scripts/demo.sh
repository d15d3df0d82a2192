#!/usr/bin/env bash
# Installs what is missing, builds Chiaro, and renders the built-in demo scene to chiaro.png
# (arguments go to `chiaro render`). It builds the whole workspace, as scripts/test.sh
# does, so that neither compiles again after the other.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh
cargo build --release --workspace
"${CARGO_TARGET_DIR:-target}/release/chiaro" render "$@"
