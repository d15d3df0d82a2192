#!/usr/bin/env bash
# The browser build. `build`: compiles chiaro-web for wasm32 (release), makes its JS glue
# with wasm-bindgen (the CLI of the same version as the crate in Cargo.lock, installed
# with cargo when missing) and puts the page in target/web/ (index.html, chiaro_web.js,
# chiaro_web_bg.wasm) with the test scenes under target/web/scenes/ (CARGO_TARGET_DIR
# moves target/). `serve [PORT]`: serves target/web/ on localhost (default port 8080).
set -euo pipefail
cd "$(dirname "$0")/.."
target_dir="${CARGO_TARGET_DIR:-target}"
out="$target_dir/web"

bindgen_version() {
    awk '/^name = "wasm-bindgen"$/ { getline; gsub(/version = |"/, ""); print; exit }' Cargo.lock
}

build() {
    rustup target list --installed 2>/dev/null | grep -qx wasm32-unknown-unknown ||
        rustup target add wasm32-unknown-unknown
    local version
    version="$(bindgen_version)"
    if [[ "$(wasm-bindgen --version 2>/dev/null)" != "wasm-bindgen $version" ]]; then
        echo "web: installing wasm-bindgen-cli $version"
        cargo install --quiet wasm-bindgen-cli --version "$version"
    fi
    cargo build --release --target wasm32-unknown-unknown -p chiaro-web
    rm -rf "$out"
    mkdir -p "$out"
    wasm-bindgen --target web --no-typescript --out-dir "$out" \
        "$target_dir/wasm32-unknown-unknown/release/chiaro_web.wasm"
    cp web/index.html "$out/"
    # The repository's test scenes, so the page and its tests load them by relative URL.
    cp -r tests/assets "$out/scenes"
    echo "web: built $out ($(du -k "$out/chiaro_web_bg.wasm" | cut -f1) KiB wasm, $(gzip -9c "$out/chiaro_web_bg.wasm" | wc -c | awk '{printf "%d", $1/1024}') KiB gzipped)"
}

serve() {
    local port="${1:-8080}"
    [[ -f "$out/index.html" ]] || build
    echo "web: http://localhost:$port/index.html"
    exec python3 -m http.server "$port" --bind 127.0.0.1 --directory "$out"
}

case "${1:-}" in
    build) build ;;
    serve) shift; serve "$@" ;;
    *) echo "usage: scripts/web.sh build | serve [PORT]" >&2; exit 2 ;;
esac
