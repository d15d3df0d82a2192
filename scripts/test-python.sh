#!/usr/bin/env bash
# Builds the Python package (python/, the chiaro-py crate, with maturin through pip) into
# a virtual environment and runs its pytest suite. CHIARO_VENV names the environment
# (default target/python-venv); arguments go to pytest.
set -euo pipefail
cd "$(dirname "$0")/.."
venv="${CHIARO_VENV:-target/python-venv}"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
"$venv/bin/python" -m pip install -q --upgrade pip
"$venv/bin/python" -m pip install -q numpy pytest
# chiaro.ray's extra, for test_ray.py (a local Ray; about 40 s and 370 MB the first time).
"$venv/bin/python" -m pip install -q "ray>=2.9"
# The package itself is rebuilt (cargo keeps what has not changed) and reinstalled.
"$venv/bin/python" -m pip install -q --force-reinstall --no-deps ./python
# test_ray.py compares chiaro.ray's files with those of the CLI's `chiaro batch`: the
# binary CHIARO_BIN names (scripts/test.sh passes the one its cargo test built), else the
# workspace's (built as scripts/demo.sh and scripts/test.sh build it; chiaro alone would
# unify features differently and compile much of it again).
if [ -z "${CHIARO_BIN:-}" ]; then
    cargo build --release --workspace -q
    CHIARO_BIN="$(realpath "${CARGO_TARGET_DIR:-target}")/release/chiaro"
fi
export CHIARO_BIN
"$venv/bin/python" -m pytest python/tests -q "$@"
