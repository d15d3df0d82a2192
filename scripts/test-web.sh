#!/usr/bin/env bash
# The browser build's tests: builds the page (scripts/web.sh build), installs the test
# driver (playwright-core, pinned in web/package-lock.json; it drives the system chromium,
# never a browser of its own) and runs web/tests/ with Node's test runner against the
# native CLI of CHIARO_BIN (default target/release/chiaro). Arguments go to `node --test`.
set -euo pipefail
cd "$(dirname "$0")/.."
command -v chromium >/dev/null 2>&1 || { echo "test-web: no chromium; run scripts/setup.sh" >&2; exit 1; }
scripts/web.sh build
(cd web && npm ci --no-audit --no-fund --loglevel=error)
export CHIARO_BIN="${CHIARO_BIN:-$(realpath "${CARGO_TARGET_DIR:-target}")/release/chiaro}"
node --test "$@" web/tests/
