"""CPU time of two source trees on the same workloads, as paired medians (a refactor's speed check).

A refactor that claims "no behaviour change" must also cost the same.  This script runs each
workload (an example scenario, solved by ``tribobem.run_scenario`` with no output folder) in a
fresh Python process per run, alternately with the tree A and the tree B on ``PYTHONPATH``
(A, B, B, A, A, B, ... so that neither side always runs first), and measures the CPU time of the solve
alone: the child reports its own ``time.process_time()`` (user + system, all its threads) around
the call, so import time is not counted.  For each
workload it prints the median of A, the median of B and the median of the paired ratios B/A
with their spread (min-max), and the same over all workloads.

Usage::

    python benchmarks/paired_cpu.py --a /path/to/base/src --b src --repeat 5
    python benchmarks/paired_cpu.py --a ../base/src --b src --examples hertz_free_boundary pulloff_sphere

Run it on an idle machine: the ratios of a loaded machine scatter by tens of per cent.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: Workloads that exercise the normal, adhesive, pull-off, coupled tangential and hysteresis
#: paths (each well under a minute).
DEFAULT_EXAMPLES = ("hertz_free_boundary", "rough_periodic", "pulloff_sphere", "partial_slip_paper_d",
                    "hysteresis_mindlin", "capillary_rough_sio2")

CHILD = """
import sys, time, warnings, json
warnings.simplefilter("ignore")
import tribobem
t = time.process_time()
tribobem.run_scenario(sys.argv[1], outdir=None, progress=False, warn=False)
print(json.dumps({"cpu": time.process_time() - t, "file": tribobem.__file__}))
"""


def one_run(src: str, example: Path) -> float:
    """CPU seconds of one solve of ``example`` with the tree ``src`` first on the path."""
    env = dict(os.environ, PYTHONPATH=str(Path(src).resolve()), MPLBACKEND="Agg")
    out = subprocess.run([sys.executable, "-c", CHILD, str(example)], env=env, capture_output=True, text=True,
                         check=True, cwd=ROOT)
    record = json.loads(out.stdout.strip().splitlines()[-1])
    if not record["file"].startswith(str(Path(src).resolve())):
        raise SystemExit(f"the child imported {record['file']}, not the tree {src}")
    return record["cpu"]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--a", required=True, help="source folder of tree A (the baseline), e.g. ../base/src")
    ap.add_argument("--b", required=True, help="source folder of tree B (the change)")
    ap.add_argument("--repeat", type=int, default=5, help="runs per tree and workload (default 5)")
    ap.add_argument("--examples", nargs="*", default=list(DEFAULT_EXAMPLES),
                    help="example stems under examples/ (default: %(default)s)")
    args = ap.parse_args(argv)
    all_ratios = []
    print(f"{'workload':28s} {'A median (s)':>12s} {'B median (s)':>12s} {'B/A median':>10s} {'B/A min-max':>14s}")
    for stem in args.examples:
        example = ROOT / "examples" / f"{stem}.toml"
        a_times, b_times = [], []
        for k in range(args.repeat):
            order = ("a", "b") if k % 2 == 0 else ("b", "a")
            for side in order:
                (a_times if side == "a" else b_times).append(one_run(args.a if side == "a" else args.b, example))
        ratios = [b / a for a, b in zip(a_times, b_times)]
        all_ratios += ratios
        print(f"{stem:28s} {statistics.median(a_times):12.3f} {statistics.median(b_times):12.3f} "
              f"{statistics.median(ratios):10.3f} {min(ratios):6.3f}-{max(ratios):.3f}", flush=True)
    print(f"{'all':28s} {'':12s} {'':12s} {statistics.median(all_ratios):10.3f} "
          f"{min(all_ratios):6.3f}-{max(all_ratios):.3f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
