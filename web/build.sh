#!/usr/bin/env bash
# Builds the page into web/dist: the csgkit-wasm crate for wasm32 in release, its JavaScript
# glue by wasm-bindgen, the example files (written by that module), and the page's scripts
# bundled by esbuild with three.js. Everything the page loads is in dist/: it works offline.
#
# Needs: the wasm32-unknown-unknown target (`rustup target add wasm32-unknown-unknown`), Node.js
# and npm. The wasm-bindgen CLI must be the version of the wasm-bindgen crate in Cargo.lock: it
# is installed from crates.io into $CSGKIT_TOOLS (default ~/.cache/csgkit/tools) when missing.
set -euo pipefail
web="$(cd "$(dirname "$0")" && pwd)"
root="$(dirname "$web")"
target="${CARGO_TARGET_DIR:-$root/target}"
tools="${CSGKIT_TOOLS:-$HOME/.cache/csgkit/tools}"
dist="$web/dist"

cargo build --manifest-path "$root/Cargo.toml" -p csgkit-wasm --release --target wasm32-unknown-unknown

version="$(grep -A1 '^name = "wasm-bindgen"$' "$root/Cargo.lock" | sed -n 's/^version = "\(.*\)"$/\1/p')"
if [[ "$("$tools/bin/wasm-bindgen" --version 2>/dev/null)" != "wasm-bindgen $version" ]]; then
  echo "installing wasm-bindgen-cli $version into $tools"
  # Not --locked: the CLI's own lock file names a webpki-roots release crates.io no longer
  # serves (it is only used by the CLI's test runner, to download browsers).
  cargo install wasm-bindgen-cli --version "$version" --root "$tools"
fi

rm -rf "$dist"
mkdir -p "$dist"
"$tools/bin/wasm-bindgen" --target web --out-dir "$dist/pkg" \
  "$target/wasm32-unknown-unknown/release/csgkit_wasm.wasm"

cd "$web"
if [[ ! -d node_modules || package-lock.json -nt node_modules ]]; then
  npm ci --no-audit --no-fund
fi
node examples.mjs "$dist"
node_modules/.bin/esbuild src/main.js src/worker.js bench/bench.js --bundle --format=esm --minify \
  --alias:csgkit-wasm=./dist/pkg/csgkit_wasm.js --outdir="$dist" --outbase=. --entry-names='[name]' \
  --external:node:module --log-level=warning
cp src/index.html src/style.css "$dist/"
cp bench/index.html "$dist/bench.html"
cp node_modules/manifold-3d/manifold.wasm "$dist/"
echo "built $dist"
