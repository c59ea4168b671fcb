#!/usr/bin/env bash
# The profile-guided release build of the command-line tool: target/pgo/csgkit.
#
# Builds csgkit instrumented, runs it over scripts/pgo_train.py's workload (booleans unlike
# the peers harness's cases), merges the counts with the toolchain's llvm-profdata, and
# builds again with them, so LLVM lays out and inlines by measured frequencies. Same source,
# same results (the profile changes no arithmetic); on the peers harness's cases the op time
# is 2-35 % lower than with `cargo build --release` (crates/csgkit/benches/README.md).
# Needs rustup (for its llvm-tools component, which the script adds) and python3; takes
# about five minutes (two release builds).
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v rustup >/dev/null; then
    echo "pgo-build.sh: needs rustup, for the llvm-tools component (llvm-profdata)" >&2
    exit 1
fi
rustup component add llvm-tools >/dev/null
sysroot="$(rustc --print sysroot)"
profdata="$(find "$sysroot/lib/rustlib" -name llvm-profdata -type f -print -quit)"
if [[ -z "$profdata" ]]; then
    echo "pgo-build.sh: llvm-profdata not found under $sysroot" >&2
    exit 1
fi
# An explicit target keeps the flags off build scripts and proc macros, so only csgkit's own
# code is instrumented and profiled. The user's RUSTFLAGS stay; the profile's file names are
# the script's.
host="$(rustc -vV | sed -n 's/^host: //p')"
unset CARGO_ENCODED_RUSTFLAGS LLVM_PROFILE_FILE
flags="${RUSTFLAGS:-}"
raw="$PWD/target/pgo-profiles/raw"
merged="$PWD/target/pgo-profiles/merged.profdata"
rm -rf "$raw" && mkdir -p "$raw"
RUSTFLAGS="$flags -Cprofile-generate=$raw" CARGO_TARGET_DIR=target/pgo-generate \
    cargo build --release --locked -p csgkit-cli --target "$host"
python3 scripts/pgo_train.py "target/pgo-generate/$host/release/csgkit"
"$profdata" merge -o "$merged" "$raw"
# Laid out for a cold process: the harness times each boolean as a fresh process's first,
# whose small cases pay more for instruction fetch (cache and TLB misses) than for arithmetic.
# `keep-text-section-prefix` keeps the functions the profile calls hot together in one
# `.text.hot` section (1 MB of the 4.6 MB of code) instead of spread among the cold ones, and
# ext-TSP block placement orders each function's blocks by the profile's edge counts for
# fewer taken branches and fetched lines. Fresh-CLI op against the same build without the
# two, medians of 15-21 interleaved runs: cube_minus_itself 0.233 -> 0.187 ms, rotated_z_union
# 0.907 -> 0.853, Menger level 1 0.741 -> 0.661, sphere_sphere_1k_union 2.16 -> 2.09; the
# cases of ten thousand faces and more within their noise. Fat LTO on top was slower there
# (model_fertility_union_cylinder 12.1 -> 13.9 ms).
layout="-Clink-arg=-Wl,-z,keep-text-section-prefix -Cllvm-args=-enable-ext-tsp-block-placement"
RUSTFLAGS="$flags -Cprofile-use=$merged $layout" CARGO_TARGET_DIR=target/pgo-use \
    cargo build --release --locked -p csgkit-cli --target "$host"
mkdir -p target/pgo
cp "target/pgo-use/$host/release/csgkit" target/pgo/csgkit
echo "pgo-build.sh: target/pgo/csgkit"
