#!/usr/bin/env bash
# Runs every fuzz target (or those named) for SECONDS each (default 600), two at a time, one
# thread each, and prints one line per target: executions, coverage, corpus size, crashes.
# Crashes land in fuzz/artifacts/<target>/; replay one with
#   cargo +nightly fuzz run -O -a -s none TARGET fuzz/artifacts/TARGET/crash-...
# Usage: fuzz/run.sh [SECONDS] [TARGET...]   (after fuzz/seed.sh)
set -uo pipefail
cd "$(dirname "$0")"
seconds=${1:-600}
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && mapfile -t targets < <(cargo +nightly fuzz list)
cargo +nightly fuzz build -O -a -s none >/dev/null 2>&1 || { echo "fuzz build failed" >&2; exit 1; }
mkdir -p logs
run_one() {
    local target=$1
    mkdir -p "corpus/$target" "artifacts/$target"
    # -timeout: an input that takes 10 s is a hang; -rss_limit_mb: one that needs 2 GiB is a
    # memory blow-up. Both count as crashes. -fork keeps fuzzing after a crash.
    RAYON_NUM_THREADS=1 cargo +nightly fuzz run -O -a -s none "$target" -- \
        -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -fork=1 -ignore_crashes=1 \
        -ignore_timeouts=1 -ignore_ooms=1 -print_final_stats=1 >"logs/$target.log" 2>&1
    local execs cov corpus crashes
    # Fork mode's status lines start with the executions so far: "#19031: cov: 885 ...".
    execs=$(grep -o '^#[0-9]*: cov' "logs/$target.log" | tail -1 | tr -dc '0-9')
    cov=$(grep -o 'cov: [0-9]*' "logs/$target.log" | tail -1 | awk '{print $2}')
    corpus=$(ls "corpus/$target" | wc -l)
    crashes=$(ls "artifacts/$target" | wc -l)
    printf '%-20s %6ss  execs %-10s cov %-6s corpus %-6s crashes %s\n' \
        "$target" "$seconds" "${execs:-?}" "${cov:-?}" "$corpus" "$crashes"
}
export -f run_one
export seconds
printf '%s\n' "${targets[@]}" | xargs -P 2 -I{} bash -c 'run_one {}'
