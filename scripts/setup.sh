#!/usr/bin/env bash
# Installs what Chiaro needs on a fresh Debian/Ubuntu machine: a C/C++ toolchain (the
# FLIP image metric in the tests builds C++), the Vulkan loader, Mesa's software Vulkan
# driver (lavapipe) when no Vulkan driver is present, Python's venv for the Python
# package, and Node.js and chromium for the browser build's tests. Rust comes from rustup.
set -euo pipefail

as_root() {
    if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi
}

# A driver's manifest in either folder, and the loader. (One `ls` of both globs fails when
# either folder is empty; `grep -q` on a pipe can fail it under pipefail.)
have_vulkan_driver() {
    { compgen -G '/usr/share/vulkan/icd.d/*.json' || compgen -G '/etc/vulkan/icd.d/*.json'; } >/dev/null &&
        [[ "$(ldconfig -p 2>/dev/null)" == *libvulkan.so.1* ]]
}

packages=()
command -v cc >/dev/null 2>&1 && command -v c++ >/dev/null 2>&1 || packages+=(build-essential)
command -v pkg-config >/dev/null 2>&1 || packages+=(pkg-config)
have_vulkan_driver || packages+=(libvulkan1 mesa-vulkan-drivers)
command -v curl >/dev/null 2>&1 || packages+=(curl ca-certificates)
# Python with venv and pip, for the Python package and its tests.
python3 -c 'import venv, ensurepip' >/dev/null 2>&1 || packages+=(python3 python3-venv python3-pip)
# A virtual X display for the windowed test of `chiaro view`.
command -v xvfb-run >/dev/null 2>&1 || packages+=(xvfb xauth)
# The browser build's tests: Node.js with npm drives Debian's chromium (WebGPU on its
# SwiftShader) through playwright-core.
command -v node >/dev/null 2>&1 && command -v npm >/dev/null 2>&1 || packages+=(nodejs npm)
command -v chromium >/dev/null 2>&1 || packages+=(chromium)

if [ ${#packages[@]} -gt 0 ]; then
    if command -v apt-get >/dev/null 2>&1; then
        echo "setup: installing ${packages[*]}"
        as_root apt-get update -qq
        DEBIAN_FRONTEND=noninteractive as_root apt-get install -y -qq "${packages[@]}" >/dev/null
    else
        echo "setup: please install: ${packages[*]} (no apt-get here)" >&2
        exit 1
    fi
fi

if ! command -v cargo >/dev/null 2>&1; then
    if [ -x "$HOME/.cargo/bin/cargo" ]; then
        export PATH="$HOME/.cargo/bin:$PATH"
    else
        echo "setup: installing Rust with rustup"
        curl --proto '=https' --tlsv1.2 -sSf https://sh.rustup.rs | sh -s -- -y --profile minimal
        export PATH="$HOME/.cargo/bin:$PATH"
    fi
fi
