#!/usr/bin/env bash
# Builds the Python package's wheel, manylinux_2_28-compliant, into target/wheels/ and
# prints its path. The extension links through zig (maturin --zig) against glibc 2.28's
# symbols, so `pip install target/wheels/chiaro-*.whl` works on any x86-64 Linux with
# glibc 2.28 or newer and a Vulkan driver (Mesa's lavapipe will do), whatever glibc built
# it. maturin checks the extension's symbols against the tag before it writes the wheel
# (auditwheel's rules), and this script checks the tag the file carries.
# CHIARO_VENV names the virtual environment that holds maturin and zig (default
# target/python-venv).
set -euo pipefail
cd "$(dirname "$0")/.."
venv="${CHIARO_VENV:-target/python-venv}"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
"$venv/bin/python" -m pip install -q "maturin>=1.9,<2" "ziglang>=0.13"
out="$(realpath -m "${CARGO_TARGET_DIR:-target}")/wheels"
mkdir -p "$out"
rm -f "$out"/chiaro-*.whl
venv_bin="$(realpath "$venv")/bin"
# maturin finds zig (the ziglang package) and the interpreter on PATH.
(cd python && PATH="$venv_bin:$PATH" "$venv_bin/maturin" build --release --zig \
    --compatibility manylinux_2_28 --out "$out" --quiet) >&2
wheel="$(ls "$out"/chiaro-*.whl)"
case "$(basename "$wheel")" in
    *-manylinux_2_28_x86_64*.whl | *.manylinux_2_28_x86_64*.whl) ;;
    *)
        echo "wheel.sh: $wheel is not tagged manylinux_2_28_x86_64" >&2
        exit 1
        ;;
esac
echo "$wheel"
