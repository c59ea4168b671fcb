"""Exact booleans over a folder of mesh pairs with Dask: one boolean per task, each result
written as a file, every failure recorded with its pair and message, none fatal.

    python batch_dask.py FOLDER -o OUT                 # pairs found by name, local cluster
    python batch_dask.py FOLDER -o OUT --pairs pairs.txt --workers 4
    python batch_dask.py FOLDER -o OUT --scheduler tcp://scheduler:8786

Pairs are either listed in a text file, one ``OP A B`` line each (OP is union,
intersection, difference or xor; A and B are paths relative to FOLDER; ``#`` starts a
comment), or found in FOLDER: two mesh files whose names differ only by a final A/B, a/b or
left/right (``ballA.off`` and ``ballB.off``, ``part_left.obj`` and ``part_right.obj``),
combined with ``--op`` (union by default).

Each task reads its two files, computes the boolean with csgkit and writes
``OUT/<A>__<op>__<B>.<format>``; it returns a record (pair, status, output, faces, volume,
seconds, or the error's type and message). Records are collected as tasks finish, written to
``OUT/report.json`` and summarised; the exit status is 1 when any pair failed.

Without ``--scheduler`` the script starts a ``LocalCluster`` of ``--workers`` processes with
one thread each (csgkit uses every core of its worker for one boolean). On a real cluster,
start ``dask scheduler`` on one machine and ``dask worker tcp://scheduler:8786
--nthreads 1`` on each worker machine, with csgkit installed
(``pip install ./crates/csgkit-py``) and FOLDER and OUT on a file system every worker
mounts at the same path; then pass ``--scheduler tcp://scheduler:8786``.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
import time
from pathlib import Path
from typing import Any, Dict, List, Optional, Tuple

MESH_SUFFIXES = {".obj", ".stl", ".ply", ".off"}
OPERATIONS = ("union", "intersection", "difference", "xor")
#: A file stem that ends in the first or the second name of a pair.
PAIR_STEM = re.compile(r"^(?P<base>.*?)(?P<side>A|B|a|b|left|right|Left|Right)$")
SECOND = {"A": "B", "a": "b", "left": "right", "Left": "Right"}

Pair = Tuple[str, str, str]  # (operation, first path, second path)


def find_pairs(folder: Path, operation: str = "union") -> List[Pair]:
    """The pairs of mesh files in ``folder`` whose stems differ only by a final A/B, a/b or
    left/right, in name order."""
    files = {p.stem: p for p in sorted(folder.iterdir()) if p.suffix.lower() in MESH_SUFFIXES}
    pairs = []
    for stem, path in files.items():
        match = PAIR_STEM.match(stem)
        if match is None or match["side"] not in SECOND:
            continue
        other = files.get(match["base"] + SECOND[match["side"]])
        if other is not None:
            pairs.append((operation, str(path), str(other)))
    return pairs


def read_pairs(listing: Path, folder: Path) -> List[Pair]:
    """The ``OP A B`` lines of ``listing``, paths taken relative to ``folder``."""
    pairs = []
    for number, line in enumerate(listing.read_text().splitlines(), start=1):
        words = line.split("#", 1)[0].split()
        if not words:
            continue
        if len(words) != 3 or words[0] not in OPERATIONS:
            raise SystemExit(f"{listing}:{number}: expected 'OP A B' with OP in {OPERATIONS}")
        pairs.append((words[0], str(folder / words[1]), str(folder / words[2])))
    return pairs


def run_pair(pair: Pair, out_dir: str, extension: str) -> Dict[str, Any]:
    """One task: the boolean of one pair, written to ``out_dir``; failures become records."""
    import csgkit  # imported on the worker

    operation, first, second = pair
    output = Path(out_dir) / f"{Path(first).stem}__{operation}__{Path(second).stem}.{extension}"
    record: Dict[str, Any] = {"operation": operation, "first": first, "second": second}
    start = time.perf_counter()
    try:
        result = csgkit.boolean(operation, [csgkit.load(first), csgkit.load(second)])
        csgkit.save(result, output)
        report = csgkit.check(result, self_intersections=False)
        record.update(status="ok", output=str(output), faces=report["faces"],
                      volume=report["volume"])
    except Exception as error:  # every failure is one pair's record, never the batch's end
        record.update(status="error", error=f"{type(error).__name__}: {error}")
    record["seconds"] = time.perf_counter() - start
    return record


def run_batch(client: Any, pairs: List[Pair], out_dir: Path, extension: str = "ply") -> List[Dict[str, Any]]:
    """Submits one task per pair and collects the records as tasks finish (a task that dies
    with its worker is recorded as a failure too), in the order of ``pairs``."""
    from dask.distributed import as_completed

    out_dir.mkdir(parents=True, exist_ok=True)
    futures = client.map(run_pair, pairs, out_dir=str(out_dir.resolve()), extension=extension,
                         pure=False)
    index = {future.key: k for k, future in enumerate(futures)}
    records: List[Optional[Dict[str, Any]]] = [None] * len(pairs)
    for future in as_completed(futures):
        k = index[future.key]
        if future.status == "finished":
            records[k] = future.result()
        else:
            error = future.exception()
            operation, first, second = pairs[k]
            records[k] = {"operation": operation, "first": first, "second": second,
                          "status": "error", "error": f"{type(error).__name__}: {error}"}
    return [record for record in records if record is not None]


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("folder", type=Path, help="the folder of mesh files")
    parser.add_argument("-o", "--output", type=Path, required=True, help="where results go")
    parser.add_argument("--pairs", type=Path, help="a file of 'OP A B' lines")
    parser.add_argument("--op", choices=OPERATIONS, default="union",
                        help="the operation of pairs found by name")
    parser.add_argument("--scheduler", help="a running scheduler's address, tcp://host:8786")
    parser.add_argument("--workers", type=int, default=2, help="local cluster worker processes")
    parser.add_argument("--format", default="ply", help="output extension (PLY keeps provenance)")
    args = parser.parse_args(argv)

    from dask.distributed import Client, LocalCluster

    pairs = read_pairs(args.pairs, args.folder) if args.pairs else find_pairs(args.folder, args.op)
    if not pairs:
        print(f"no pairs in {args.folder}", file=sys.stderr)
        return 1
    if args.scheduler:
        client = Client(args.scheduler)
    else:
        cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1,
                               dashboard_address=None)
        client = Client(cluster)
    with client:
        records = run_batch(client, pairs, args.output, args.format)
    (args.output / "report.json").write_text(json.dumps(records, indent=1))
    failed = [r for r in records if r["status"] != "ok"]
    for r in records:
        name = f"{r['operation']} {Path(r['first']).name} {Path(r['second']).name}"
        outcome = (f"{r['faces']} faces, volume {r['volume']:.6g}" if r["status"] == "ok"
                   else r["error"])
        print(f"{name}: {outcome} ({r['seconds']:.2f} s)" if "seconds" in r else f"{name}: {outcome}")
    print(f"{len(records) - len(failed)} of {len(records)} pairs done, {len(failed)} failed; "
          f"report: {args.output / 'report.json'}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
