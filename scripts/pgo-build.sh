#!/usr/bin/env bash
# The profile-guided release build of the command-line tool: target/pgo/csgkit.
#
# Builds csgkit instrumented, runs it over scripts/pgo_train.py's workload (booleans unlike
# the peers harness's cases), merges the counts with the toolchain's llvm-profdata, and
# builds again with them, so LLVM lays out and inlines by measured frequencies. Same source,
# same results (the profile changes no arithmetic); the peers harness's cases run 3-14 %
# faster (crates/csgkit/benches/README.md). Needs rustup's llvm-tools component, which the
# script installs, and python3.
set -euo pipefail
cd "$(dirname "$0")/.."
rustup component add llvm-tools >/dev/null
sysroot="$(rustc --print sysroot)"
profdata="$(find "$sysroot/lib/rustlib" -name llvm-profdata -type f -print -quit)"
if [[ -z "$profdata" ]]; then
    echo "pgo-build.sh: llvm-profdata not found under $sysroot" >&2
    exit 1
fi
raw="$PWD/target/pgo-profiles/raw"
merged="$PWD/target/pgo-profiles/merged.profdata"
rm -rf "$raw" && mkdir -p "$raw"
RUSTFLAGS="-Cprofile-generate=$raw" CARGO_TARGET_DIR=target/pgo-generate \
    cargo build --release --locked -p csgkit-cli
python3 scripts/pgo_train.py target/pgo-generate/release/csgkit
"$profdata" merge -o "$merged" "$raw"
RUSTFLAGS="-Cprofile-use=$merged" CARGO_TARGET_DIR=target/pgo-use \
    cargo build --release --locked -p csgkit-cli
mkdir -p target/pgo
cp target/pgo-use/release/csgkit target/pgo/csgkit
echo "pgo-build.sh: target/pgo/csgkit"
