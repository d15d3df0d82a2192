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
# The package itself is rebuilt (cargo keeps what has not changed) and reinstalled.
"$venv/bin/python" -m pip install -q --force-reinstall --no-deps ./python
"$venv/bin/python" -m pytest python/tests -q "$@"
