"""Benchmark (issue 30, item 2): VSL-3D with a second depth camera.

For each VSL-3D experiment named, the same seeded trials run with ``--views 1`` (the paper's
single view) and ``--views 2`` (a second sensor across the table, the clouds fused by the
sensors' known poses): the success rates side by side with their 95 % intervals, the CPU
seconds per trial and the cost ratio of two views to one, and the failures' causes. The cost is
CPU seconds per trial (a worker's first trial also imports torch and the simulator: the median
per trial and the median of the paired per-seed ratios, which such an outlier does not move).
Target: ``--views 2`` >= 99.5 % for table-cleaning and stacking over seeds 0-199 each, at most
1.5 times the cost of one view.

    python benchmarks/bench_views.py [EXPERIMENT ...] [--trials N] [--seed S] [--workers W]
                                     [--views 1 2] [--out FILE.json] [--json]
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
from collections import Counter
from pathlib import Path

from vslsp.tasks import get_task, run_trials
from vslsp.tasks.statistics import wilson_interval

EXPERIMENTS = ("table-cleaning", "stacking")


def measure(name: str, seeds: list[int], views: int, workers: int) -> dict:
    """The trials of ``seeds`` of experiment ``name`` with ``views`` depth cameras."""
    task = get_task(name, views=views)
    results = run_trials(task, seeds, workers=workers).results
    successes = sum(r.success for r in results)
    low, high = wilson_interval(successes, len(results))
    return {
        "experiment": name,
        "views": views,
        "trials": len(results),
        "successes": successes,
        "rate": successes / len(results),
        "interval_95": [round(low, 3), round(high, 3)],
        "cpu_s": {r.seed: round(r.cpu_s, 3) for r in results},
        "median_cpu_s": round(statistics.median(r.cpu_s for r in results), 3),
        "failures": dict(Counter(r.cause for r in results if not r.success)),
        "failed": {r.seed: r.error for r in results if not r.success},
    }


def cost_ratio(one: dict, two: dict) -> dict:
    """Two views' cost against one's on the same seeds: the ratio of the medians per trial and
    the median of the per-seed ratios."""
    paired = [two["cpu_s"][s] / one["cpu_s"][s] for s in one["cpu_s"] if s in two["cpu_s"] and one["cpu_s"][s] > 0]
    return {
        "ratio_of_medians": round(two["median_cpu_s"] / one["median_cpu_s"], 3),
        "median_paired_ratio": round(statistics.median(paired), 3) if paired else None,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("experiments", nargs="*", default=list(EXPERIMENTS))
    parser.add_argument("--trials", type=int, default=50)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--views", type=int, nargs="+", default=[2, 1], choices=[1, 2])
    parser.add_argument("--out", type=Path, default=None, help="also write the rows here (after each one)")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    seeds = list(range(args.seed, args.seed + args.trials))
    rows = []
    for views in args.views:
        for name in args.experiments:
            rows.append(measure(name, seeds, views, args.workers))
            row = rows[-1]
            print(
                f"{name} --views {views}: {row['successes']}/{row['trials']}, median {row['median_cpu_s']} cpu s "
                f"per trial, failures {row['failed']}",
                file=sys.stderr,
                flush=True,
            )
            if args.out is not None:
                args.out.write_text(json.dumps({"seed": args.seed, "rows": rows}))
    ratios = {}
    for name in args.experiments:
        found = {r["views"]: r for r in rows if r["experiment"] == name}
        if 1 in found and 2 in found:
            ratios[name] = cost_ratio(found[1], found[2])
    if args.json:
        print(json.dumps({"seed": args.seed, "rows": rows, "cost_ratio": ratios}))
        return
    print(f"VSL-3D with one and two depth cameras, seeds {seeds[0]}-{seeds[-1]}")
    print(f"{'experiment':<16} {'views':>5} {'success':>9} {'rate':>7} {'95 % interval':>15} {'cpu s/trial':>11}")
    for name in args.experiments:
        for row in sorted((r for r in rows if r["experiment"] == name), key=lambda r: r["views"]):
            low, high = row["interval_95"]
            print(
                f"{name:<16} {row['views']:>5} {row['successes']:>4}/{row['trials']:<4} {100 * row['rate']:>6.1f}% "
                f"{100 * low:>6.1f}-{100 * high:<6.1f}% {row['median_cpu_s']:>11}"
            )
            for seed, error in row["failed"].items():
                print(f"    seed {seed}: {error}")
        if name in ratios:
            ratio = ratios[name]
            print(
                f"{name}: two views cost {ratio['ratio_of_medians']}x one per trial (median of paired "
                f"ratios {ratio['median_paired_ratio']}x; target <= 1.5x)"
            )


if __name__ == "__main__":
    main()
