#!/usr/bin/env bash
# Build the raytree inspector as a static web page into web/dist/ (index.html, JS, wasm):
#   web/build.sh && python3 -m http.server -d web/dist   # then open http://localhost:8000
# Installs what it needs when missing: rustup's wasm32 target, and wasm-bindgen-cli at exactly
# the version of wasm-bindgen in Cargo.lock (cached in ~/.cargo/bin; about 7-14 minutes to
# build once). With RAYTREE_WASM_OPT=1 it also runs npm binaryen's `wasm-opt -Oz` (not
# Debian's binaryen 108, whose output breaks the page). Environment: CARGO_TARGET_DIR as cargo.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(dirname "$here")"
cd "$root"
target_dir="${CARGO_TARGET_DIR:-$root/target}"
out="$here/dist"

say() { printf 'web/build.sh: %s\n' "$*" >&2; }

if ! rustup target list --installed | grep -qx wasm32-unknown-unknown; then
  say "installing the wasm32-unknown-unknown target"
  rustup target add wasm32-unknown-unknown
fi

# The CLI must match the library that generated the bindings, byte for byte in its schema.
want="$(awk '/^name = "wasm-bindgen"$/ { getline; gsub(/version = |"/, ""); print; exit }' Cargo.lock)"
[ -n "$want" ] || { say "no wasm-bindgen in Cargo.lock"; exit 1; }
have="$(wasm-bindgen --version 2>/dev/null | awk '{ print $2 }' || true)"
if [ "$have" != "$want" ]; then
  say "installing wasm-bindgen-cli $want (found: ${have:-none}); this takes several minutes"
  # Not --locked: the CLI's own lock file does not build with this toolchain.
  cargo install wasm-bindgen-cli --version "$want"
fi

say "building the wasm (release)"
cargo build --release --locked -p raytree-web --lib --target wasm32-unknown-unknown
wasm="$target_dir/wasm32-unknown-unknown/release/raytree_web.wasm"

rm -rf "$out"
mkdir -p "$out"
wasm-bindgen --target web --no-typescript --out-dir "$out" "$wasm"
if [ "${RAYTREE_WASM_OPT:-0}" = 1 ]; then
  say "wasm-opt -Oz (npm binaryen)"
  (cd "$here" && npm ci --no-audit --no-fund >/dev/null)
  "$here/node_modules/.bin/wasm-opt" -Oz --enable-bulk-memory --enable-nontrapping-float-to-int \
    --enable-sign-ext --enable-mutable-globals --enable-reference-types --enable-multivalue \
    -o "$out/raytree_web_bg.wasm.opt" "$out/raytree_web_bg.wasm"
  mv "$out/raytree_web_bg.wasm.opt" "$out/raytree_web_bg.wasm"
fi
cp "$here/static/index.html" "$out/"
size="$(stat -c %s "$out/raytree_web_bg.wasm")"
gz="$(gzip -9c "$out/raytree_web_bg.wasm" | wc -c)"
say "wrote $out: raytree_web_bg.wasm $((size / 1024)) KiB ($((gz / 1024)) KiB gzipped)"
say "serve it with: python3 -m http.server -d web/dist"
