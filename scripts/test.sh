#!/usr/bin/env bash
# Runs every test: the Rust workspace's, then the Python package's (scripts/test-python.sh
# builds it into a virtual environment and runs pytest), then the browser build's
# (scripts/test-web.sh builds the page and drives chromium). Arguments go to pytest.
set -euo pipefail
cd "$(dirname "$0")/.."
# The workspace build scripts/demo.sh makes first (the CLI, the viewer, the Python
# extension), so that the demo needs no compile after the tests; the tests then compile
# only their own targets on top of it.
cargo build --release --workspace
cargo test --release --workspace
# The CLI that cargo test built, for the Python tests that compare with `chiaro batch`.
CHIARO_BIN="$(realpath "${CARGO_TARGET_DIR:-target}")/release/chiaro" scripts/test-python.sh "$@"
CHIARO_BIN="$(realpath "${CARGO_TARGET_DIR:-target}")/release/chiaro" scripts/test-web.sh
