#!/usr/bin/env python3
"""Where csgkit's exact booleans spend their time: per stage and per source file.

    cargo build --profile profiling -p csgkit-cli
    python3 crates/csgkit/benches/profile.py --csgkit target/profiling/csgkit \
        --cases ../shared/peers/cases [CASE ...] > profile.md

For each peers-harness case (default: one per family), runs the case's expression through the
CLI: first with --stats (op time and stage seconds, median of three runs), then under
`perf record -e cpu-clock` (software sampling: this machine has no hardware counters), and
sorts the samples by source file, which follows inlined code to the file it came from. The
kernel's files are its cascade's tiers: interval.rs is the filter, arith.rs the 128-bit
integer stage (and the big-integer glue), double_double.rs the double-doubles, expansion.rs
the expansions, num-bigint the big integers, and robust the explicit orient2d / orient3d
shortcut. Prints Markdown tables.
Needs `perf` (Debian package linux-perf) and a build with line tables: the `profiling` profile
(release with `debug = 1`).
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

DEFAULT_CASES = [
    "cube_cube_partial_face",
    "rotated_xyz_union",
    "sphere_sphere_1k_union",
    "sphere_sphere_100k_union",
    "sphere_sphere_1M_union",
    "menger_2",
    "menger_3",
    "boxes_union_1000",
    "model_bunny_watertight_minus_offset",
]

TIERS = [
    ("predicates: filter (kernel/interval.rs)", lambda f: f.endswith("src/kernel/interval.rs")),
    ("predicates: 128-bit integers (kernel/arith.rs)", lambda f: f.endswith("src/kernel/arith.rs")),
    ("predicates: double-doubles (kernel/double_double.rs)", lambda f: f.endswith("src/kernel/double_double.rs")),
    ("predicates: expansions (kernel/expansion.rs)", lambda f: f.endswith("src/kernel/expansion.rs")),
    ("predicates: big integers (num-bigint)", lambda f: "/num-bigint-" in f),
    ("predicates: formulas and points (other kernel files)", lambda f: "/src/kernel/" in f),
    ("predicates: explicit orient2d/3d (robust)", lambda f: "/robust-" in f),
    ("Linux kernel (page faults: clearing fresh pages)", lambda f: f == "[kernel]"),
    ("allocator", lambda f: "/libmimalloc-sys-" in f or "/malloc/" in f),
    ("Rust std (inlined slice, iterator, Vec code)", lambda f: f.startswith("/rustc/")),
    ("rayon (thread pool, splitting)", lambda f: "/rayon-" in f),
]


def command(csgkit, case_dir, extra):
    case = json.load(open(os.path.join(case_dir, "case.json")))
    files = [os.path.join(case_dir, f) for f in open(os.path.join(case_dir, "list.txt")).read().split()]
    op = case["expr"]["op"]
    out = os.path.join(tempfile.gettempdir(), "csgkit-profile.obj")
    return [csgkit, op, *files, "-o", out, *extra]


def stats(csgkit, case_dir):
    runs = []
    for _ in range(3):
        out = subprocess.run(command(csgkit, case_dir, ["--stats"]), capture_output=True, text=True, check=True)
        runs.append(json.loads(out.stdout))
    op = statistics.median(r["op_seconds"] for r in runs)
    stages = {k: statistics.median(r["stages"][k] for r in runs) for k in runs[0]["stages"]}
    return op, stages, runs[0]


def perf_files(csgkit, case_dir):
    data = os.path.join(tempfile.gettempdir(), "csgkit-profile.perf")
    subprocess.run(["perf", "record", "-q", "-e", "cpu-clock", "-F", "4000", "-o", data, "--",
                    *command(csgkit, case_dir, [])], check=True, capture_output=True)
    report = subprocess.run(["perf", "report", "-i", data, "--stdio", "--no-children", "--sort", "dso,srcfile",
                             "--full-source-path", "--percent-limit", "0"],
                            capture_output=True, text=True, check=True).stdout
    shares = {}
    for line in report.splitlines():
        parts = line.split()
        if len(parts) >= 2 and parts[0].endswith("%"):
            dso, source = parts[1], (parts[2] if len(parts) > 2 else "")
            key = "[kernel]" if dso == "[kernel.kallsyms]" else (source or dso)
            shares[key] = shares.get(key, 0.0) + float(parts[0].rstrip("%"))
    return shares


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--csgkit", required=True)
    ap.add_argument("--cases", required=True, help="the peers harness's cases folder")
    ap.add_argument("names", nargs="*")
    args = ap.parse_args()
    for name in args.names or DEFAULT_CASES:
        case_dir = os.path.join(args.cases, name)
        if not os.path.isdir(case_dir):
            print(f"skipping {name}: no such case in {args.cases}", file=sys.stderr)
            continue
        op, stages, first = stats(args.csgkit, case_dir)
        print(f"### {name}: op {op * 1e3:.2f} ms, {first['input_triangles']} input triangles, "
              f"{first['output_triangles']} output\n")
        print("| stage | ms | share of op |\n|---|---|---|")
        for stage, seconds in sorted(stages.items(), key=lambda kv: -kv[1]):
            if stage != "validate" and seconds >= 0.01 * op:
                print(f"| {stage} | {seconds * 1e3:.2f} | {100 * seconds / op:.0f}% |")
        print(f"| (validate, outside op) | {stages.get('validate', 0) * 1e3:.2f} | |\n")
        shares = perf_files(args.csgkit, case_dir)
        print("| samples by source (whole process) | share |\n|---|---|")
        tiers = {label: 0.0 for label, _ in TIERS}
        rest = {}
        for file, share in shares.items():
            label = next((label for label, test in TIERS if test(file)), None)
            if label:
                tiers[label] += share
            else:
                rest[file] = share
        for label, share in tiers.items():
            print(f"| {label} | {share:.1f}% |")
        for file, share in sorted(rest.items(), key=lambda kv: -kv[1])[:10]:
            short = file.split("/crates/csgkit/src/")[-1] if "/crates/csgkit/src/" in file else file
            print(f"| {short} | {share:.1f}% |")
        print()


if __name__ == "__main__":
    main()
