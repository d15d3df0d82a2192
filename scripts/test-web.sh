#!/usr/bin/env bash
# The browser build's tests: builds the page (scripts/web.sh build), installs the test
# driver (playwright-core, pinned in web/package-lock.json; it drives the system chromium,
# never a browser of its own) and runs web/tests/ with Node's test runner against the
# native CLI of CHIARO_BIN (default target/release/chiaro). Arguments go to `node --test`.
set -euo pipefail
cd "$(dirname "$0")/.."
command -v chromium >/dev/null 2>&1 || { echo "test-web: no chromium; run scripts/setup.sh" >&2; exit 1; }
# playwright-core 1.61 (web/package-lock.json) runs on Node.js 18 (Debian 12's) and later.
node_major="$(node -p 'process.versions.node.split(".")[0]')"
if (( node_major < 18 )); then
    echo "test-web: Node.js $(node --version) is too old; the browser tests need 18 or later" >&2
    exit 1
fi
scripts/web.sh build
(cd web && npm ci --no-audit --no-fund --loglevel=error)
export CHIARO_BIN="${CHIARO_BIN:-$(realpath "${CARGO_TARGET_DIR:-target}")/release/chiaro}"
# The files, not the folder: Node 21 and later read a folder argument as a file.
node --test "$@" web/tests/*.test.mjs
