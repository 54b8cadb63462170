#!/usr/bin/env bash
# The web inspector's end-to-end test in headless Chromium (web/test.mjs): builds the page
# (web/build.sh) and the native CLI it is compared with, installs Debian's chromium and npm's
# playwright-core (web/package-lock.json) when missing, and runs the test. It skips, saying
# why, only when chromium or node cannot be installed. RAYTREE_NO_BUILD=1 uses web/dist as is.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(dirname "$here")"
cd "$root"
target_dir="${CARGO_TARGET_DIR:-$root/target}"
say() { printf 'web/test.sh: %s\n' "$*" >&2; }
skip() { say "SKIPPED: $*"; exit 0; }
can_apt() { command -v apt-get >/dev/null && [ "$(id -u)" = 0 ]; }

if ! command -v chromium >/dev/null; then
  if can_apt; then
    say "installing chromium (apt-get)"
    DEBIAN_FRONTEND=noninteractive apt-get install -y chromium >/dev/null \
      || { apt-get update >/dev/null && DEBIAN_FRONTEND=noninteractive apt-get install -y chromium >/dev/null; } || true
  fi
  command -v chromium >/dev/null || skip "no chromium, and apt-get install -y chromium failed or is not allowed here"
fi
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
  if can_apt; then
    say "installing node and npm (apt-get)"
    DEBIAN_FRONTEND=noninteractive apt-get install -y nodejs npm >/dev/null || true
  fi
  command -v node >/dev/null && command -v npm >/dev/null \
    || skip "no node/npm, and apt-get install -y nodejs npm failed or is not allowed here"
fi
if [ ! -d "$here/node_modules/playwright-core" ]; then
  say "npm ci (playwright-core, binaryen)"
  (cd "$here" && npm ci --no-audit --no-fund >/dev/null) || skip "npm ci failed: cannot install playwright-core"
fi

[ "${RAYTREE_NO_BUILD:-0}" = 1 ] || "$here/build.sh"
say "building the native CLI the page is compared with"
# Default features: the binary `cargo test --release` builds (CI runs that first), not a second one.
cargo build --release --locked --bin raytree
say "running the browser test"
RAYTREE_BIN="$target_dir/release/raytree" node "$here/test.mjs"
