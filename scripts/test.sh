#!/usr/bin/env bash
# Runs every test: the Rust workspace's, then the Python package's (scripts/test-python.sh
# builds it into a virtual environment and runs pytest). Arguments go to pytest.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo test --release --workspace
scripts/test-python.sh "$@"
