#!/usr/bin/env python3
"""csgkit beside the peers under one protocol, both in process: csgkit through its Python
package, the peers through the peers harness's own adapters (its ``peerlib``).

    ../shared/peers/.venv/bin/pip install ./crates/csgkit-py
    ../shared/peers/.venv/bin/python crates/csgkit/benches/in_process.py \\
        --peers-dir ../shared/peers --results RUN --cases 'coplanar|rotated|sphere_sphere_1k'

The harness runs csgkit as a fresh command-line process per run, so every csgkit figure there
is a first run of its code, while each peer's timed runs follow a warm-up run in its process.
Here each (case, engine) runs in a fresh Python process: the operands are converted first (not
timed: ``csgkit.Mesh`` from the arrays, as the harness's ``prepare`` builds each peer's own
objects), then the operation is timed, run 0 (the first in the process: cold) and ``--runs``
more (their median: warm). csgkit's time is its call minus its ``validate`` stage, the
operands' self-intersection check, which the harness's csgkit figure (``op_seconds``) leaves
out too; the peers check nothing.

Correctness: a peer counts where the harness run given by ``--results`` (the cases must come
from it) judged it correct; csgkit's result must be a valid solid by ``csgkit.check`` with the
run's reference volume (``ref_volume``: the exact one where the case has it, else the peers'
median) to the harness's tolerance, 1e-4 relative. Prints one Markdown table: each engine's
cold and warm op time, and csgkit's ratios to the fastest correct peer, cold to cold and warm
to warm, with the geometric means and the count above 1.5×.

The package builds with ``cargo build --release`` settings (maturin), not the harness's
profile-guided binary: its figures are an upper bound for that binary's.
"""
import argparse
import json
import math
import os
import re
import statistics
import subprocess
import sys
import time

ENGINES = ["csgkit", "manifold3d", "trueform", "meshlib"]


class Csgkit:
    """The harness's adapter interface (``peerlib.Peer``) for csgkit's Python package."""

    def setup(self):
        import csgkit
        self.csgkit = csgkit

    def prepare(self, operands):
        return [self.csgkit.Mesh(V, F) for V, F in operands]

    def timed(self, expr, natives):
        start = time.perf_counter()
        result = self.csgkit.boolean(expr["op"], [natives[i] for i in expr["args"]])
        wall = time.perf_counter() - start
        return wall - result.stage_seconds.get("validate", 0.0), result

    def verdict(self, result, reference):
        report = self.csgkit.check(result)
        close = abs(report["volume"] - reference) <= 1e-4 * max(abs(reference), 1e-12)
        return bool(report["valid_solid"] and close)


class Peer:
    """A peer through the harness's adapter: ``evaluate`` is what the harness times."""

    def __init__(self, name):
        import peerlib
        self.peer = peerlib.PEERS[name]()

    def setup(self):
        self.peer.setup()

    def prepare(self, operands):
        return self.peer.stage(self.expr, self.peer.prepare(operands))

    def timed(self, expr, natives):
        start = time.perf_counter()
        result = self.peer.evaluate(expr, natives)
        return time.perf_counter() - start, result

    def verdict(self, result, reference):
        return None


def one(case_dir, engine, runs, reference):
    """Runs one engine on one case in this process; prints its cold and warm times as JSON."""
    import worker  # the harness's case loading

    meta, operands = worker.load_case(case_dir)
    adapter = Csgkit() if engine == "csgkit" else Peer(engine)
    adapter.expr = meta["expr"]
    adapter.setup()
    times, verdict = [], None
    for run in range(1 + runs):
        natives = adapter.prepare(operands)
        seconds, result = adapter.timed(meta["expr"], natives)
        times.append(seconds)
        if run == 0:
            verdict = adapter.verdict(result, reference)
            if seconds > 2.0:
                break
        del result, natives
    print(json.dumps({"cold": times[0], "warm": statistics.median(times[1:] or times),
                      "runs": len(times) - 1, "correct": verdict}))


def verdicts(peers_dir, results_dir):
    """Per case, the peers the harness run judged correct (its own rules) and its reference
    volume."""
    os.chdir(peers_dir)
    import bench

    bench.set_results_dir(os.path.abspath(results_dir))
    results = bench.load_results()
    bench.annotate(results)
    return {case: ({p for p, r in by_peer.items() if not p.startswith("csgkit") and r.get("correct")},
                   next((r["ref_volume"] for r in by_peer.values() if r.get("ref_volume") is not None),
                        None))
            for case, by_peer in results["results"].items()}


def fmt(seconds):
    return f"{seconds * 1e3:.3f} ms" if seconds < 1 else f"{seconds:.2f} s"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--peers-dir", required=True)
    ap.add_argument("--results", help="the harness run whose correctness verdicts count")
    ap.add_argument("--cases", default="coplanar|rotated|sphere_sphere_1k", help="regular expression")
    ap.add_argument("--runs", type=int, default=20, help="warm runs after the cold one")
    ap.add_argument("--one", nargs=3, metavar=("CASE_DIR", "ENGINE", "VOLUME"), help=argparse.SUPPRESS)
    args = ap.parse_args()
    peers_dir = os.path.abspath(args.peers_dir)
    sys.path.insert(0, peers_dir)
    if args.one:
        one(args.one[0], args.one[1], args.runs, float(args.one[2]))
        return
    if not args.results:
        sys.exit("in_process.py: --results RUN is needed (the harness run that judged the peers)")
    judged = verdicts(peers_dir, args.results)
    cases = sorted(c for c, (_, volume) in judged.items() if re.search(args.cases, c)
                   and volume is not None and os.path.isdir(os.path.join(peers_dir, "cases", c)))
    print("| case | csgkit cold | csgkit warm | fastest correct peer, cold | warm "
          "| ratio cold | ratio warm |\n|---|---|---|---|---|---|---|")
    ratios = {"cold": [], "warm": []}
    for case in cases:
        measured = {}
        correct, volume = judged[case]
        for engine in ENGINES:
            if engine != "csgkit" and engine not in correct:
                continue
            done = subprocess.run([sys.executable, os.path.abspath(__file__), "--peers-dir", peers_dir,
                                   "--runs", str(args.runs), "--one",
                                   os.path.join(peers_dir, "cases", case), engine, repr(volume)],
                                  capture_output=True, text=True, cwd=peers_dir)
            if done.returncode != 0:
                print(f"{case} {engine}: failed\n{done.stderr[-2000:]}", file=sys.stderr)
                continue
            measured[engine] = json.loads(done.stdout.strip().splitlines()[-1])
        ours = measured.pop("csgkit", None)
        if not ours or not ours["correct"] or not measured:
            print(f"| {case} | {'not correct' if ours else 'failed'} | | | | | |")
            continue
        row = [case, fmt(ours["cold"]), fmt(ours["warm"])]
        cold = min(measured.items(), key=lambda kv: kv[1]["cold"])
        warm = min(measured.items(), key=lambda kv: kv[1]["warm"])
        row += [f"{cold[0]} {fmt(cold[1]['cold'])}", f"{warm[0]} {fmt(warm[1]['warm'])}"]
        for kind, best in (("cold", cold), ("warm", warm)):
            ratio = ours[kind] / best[1][kind]
            ratios[kind].append(ratio)
            row.append(f"{ratio:.2f}×")
        print("| " + " | ".join(row) + " |", flush=True)
    for kind, values in ratios.items():
        if values:
            geo = math.exp(sum(map(math.log, values)) / len(values))
            print(f"\n{kind}: geometric mean over {len(values)} cases {geo:.3f}×, worst "
                  f"{max(values):.2f}×, above 1.5×: {sum(v > 1.5 for v in values)}")


if __name__ == "__main__":
    main()
