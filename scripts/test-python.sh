#!/usr/bin/env bash
# Builds the Python package's manylinux wheel (scripts/wheel.sh: python/ and the chiaro-py
# crate, through maturin), installs it into a virtual environment, checks the package
# with mypy --strict and runs its pytest suite. CHIARO_VENV names the environment
# (default target/python-venv); arguments go to pytest.
set -euo pipefail
cd "$(dirname "$0")/.."
venv="${CHIARO_VENV:-target/python-venv}"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
"$venv/bin/python" -m pip install -q --upgrade pip
"$venv/bin/python" -m pip install -q numpy pytest
# chiaro.ray's extra, for test_ray.py (a local Ray; a large download the first time).
"$venv/bin/python" -m pip install -q "ray>=2.9"
# mypy, for the strict check of the package's annotations below.
"$venv/bin/python" -m pip install -q mypy
# The package itself: the manylinux wheel scripts/wheel.sh builds (cargo keeps what has
# not changed; the script fails unless the wheel's tag is manylinux_2_28), reinstalled.
wheel="$(CHIARO_VENV="$venv" scripts/wheel.sh)"
"$venv/bin/python" -m pip install -q --force-reinstall --no-deps "$wheel"
venv_python="$(realpath "$venv")/bin/python"
(cd python && "$venv_python" -m mypy chiaro)
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
