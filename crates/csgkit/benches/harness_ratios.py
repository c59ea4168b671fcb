#!/usr/bin/env python3
"""csgkit against the fastest correct peer, case by case, from one peers-harness run.

    ../shared/peers/.venv/bin/python bench.py run --csgkit target/release/csgkit \
        --peers csgkit,manifold3d,trueform,meshlib --results-dir RUN      # in ../shared/peers
    ../shared/peers/.venv/bin/python crates/csgkit/benches/harness_ratios.py \
        --peers-dir ../shared/peers --results RUN --plot crates/csgkit/benches/scaling.png

Correctness is the harness's own judgement (its `annotate`: valid, and the volume within 1e-4
of the reference). Ratio = csgkit's op time / the fastest correct peer's op time, medians of
the timed runs; the peers are every row whose name does not start with "csgkit", so a second
csgkit build run in the same invocation (`--peer-cmd 'csgkit-plain=BIN {op} {inputs} -o {out}
--stats'`) is not its own peer, and `--ours csgkit-plain` gives its ratios. Prints one
Markdown table per family and the geometric mean over every boolean case where csgkit and a
peer are correct.

A second ratio compares first runs: every csgkit run is a fresh CLI process, whose operation
runs its code for the first time (cold caches, branch predictors, first-touch pages), while
a peer's timed runs follow a warm-up run in its process. The harness keeps that warm-up's op
time (`warmup_op_s`), the same first run of the peer's boolean code in a fresh process
(after its import and its operands' conversion, which are not timed): "cold ratio" =
csgkit's op / the fastest correct peer's warm-up op.

With --plot, op time against input
triangles for the sphere_sphere_union and menger families, every peer on one log-log plot,
with the growth exponent of each (least squares on the logs). matplotlib: pip install it into
the same venv.
"""
import argparse
import math
import os
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--peers-dir", required=True)
    ap.add_argument("--results", required=True, help="the run's --results-dir")
    ap.add_argument("--plot", help="write the scaling plot to this PNG")
    ap.add_argument("--ours", default="csgkit", help="the row whose ratios are printed")
    args = ap.parse_args()
    plot_path = os.path.abspath(args.plot) if args.plot else None
    sys.path.insert(0, os.path.abspath(args.peers_dir))
    os.chdir(args.peers_dir)
    import bench  # the harness's own loading and correctness rules

    bench.set_results_dir(os.path.abspath(args.results))
    results = bench.load_results()
    bench.annotate(results)
    rows, ratios, cold_ratios = {}, [], []
    for name, by_peer in results["results"].items():
        meta = results["cases"].get(name, {})
        if meta.get("family", "").startswith("voxelize"):
            continue
        ours = by_peer.get(args.ours)
        peers = {p: r for p, r in by_peer.items()
                 if p != args.ours and not p.startswith("csgkit") and r.get("correct")}
        best = min(peers.items(), key=lambda kv: kv[1]["op_s"], default=None)
        cold_peers = {p: r for p, r in peers.items() if r.get("warmup_op_s")}
        best_cold = min(cold_peers.items(), key=lambda kv: kv[1]["warmup_op_s"], default=None)
        ok = bool(ours and ours.get("correct"))
        ratio = ours["op_s"] / best[1]["op_s"] if ok and best else None
        cold_ratio = ours["op_s"] / best_cold[1]["warmup_op_s"] if ok and best_cold else None
        if ratio is not None:
            ratios.append(ratio)
        if cold_ratio is not None:
            cold_ratios.append(cold_ratio)
        rows.setdefault(meta.get("family", "?"), []).append(
            (name, ours, best, ok, ratio, best_cold, cold_ratio))
    for family, entries in sorted(rows.items()):
        print(f"\n#### {family}\n")
        print(f"| case | {args.ours} | fastest correct peer | ratio "
              "| fastest first run of a correct peer | cold ratio |\n|---|---|---|---|---|---|")
        for name, ours, best, ok, ratio, best_cold, cold_ratio in sorted(entries, key=lambda e: e[0]):
            mine = "—" if not ours else f"{bench.fmt_t(ours.get('op_s'))} {'✔' if ok else '⚠ ' + ours.get('status', '')}"
            theirs = f"{best[0]} {bench.fmt_t(best[1]['op_s'])}" if best else "none correct"
            theirs_cold = (f"{best_cold[0]} {bench.fmt_t(best_cold[1]['warmup_op_s'])}"
                           if best_cold else "none correct")
            print(f"| {name} | {mine} | {theirs} | {'%.2f×' % ratio if ratio else '—'} "
                  f"| {theirs_cold} | {'%.2f×' % cold_ratio if cold_ratio else '—'} |")
    for label, values in (("", ratios), ("cold ratios, against first runs: ", cold_ratios)):
        if values:
            geo = math.exp(sum(math.log(r) for r in values) / len(values))
            print(f"\n{label}Geometric mean over {len(values)} cases: {geo:.3f}×; worst "
                  f"{max(values):.2f}×; cases above 1.5×: {sum(r > 1.5 for r in values)}")
    if plot_path:
        plot(results, plot_path)


def plot(results, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(12, 5))
    for ax, family in zip(axes, ["sphere_sphere_union", "menger"]):
        names = [n for n, m in results["cases"].items() if m.get("family") == family]
        peers = sorted({p for n in names for p in results["results"].get(n, {})})
        for peer in peers:
            points = sorted((results["cases"][n]["input_triangles"], r["op_s"])
                            for n in names for p, r in results["results"].get(n, {}).items()
                            if p == peer and r.get("correct") and r.get("op_s"))
            if len(points) < 2:
                continue
            xs, ys = zip(*points)
            lx, ly = [math.log(x) for x in xs], [math.log(y) for y in ys]
            mx, my = sum(lx) / len(lx), sum(ly) / len(ly)
            slope = sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sum((a - mx) ** 2 for a in lx)
            ax.loglog(xs, ys, marker="o", label=f"{peer} (exponent {slope:.2f})")
            print(f"{family}: {peer} growth exponent {slope:.2f} over {len(xs)} sizes")
        ax.set_title(family)
        ax.set_xlabel("input triangles")
        ax.set_ylabel("op time (s), correct results only")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    main()
