"""Benchmark (issue 30, item 1): demonstrations in which the tutor also disturbs another object.

For each experiment named, the same seeded trials run twice with ``--tutor-slips P``: with the
slip detection on (every object that moved in an operation is found, the operated one told from
those disturbed) and off (the paper's VSL, which takes the change for the operation), so that
the gain is shown on the same demonstrations and new scenes. It prints, per experiment, the
success rates with their 95 % intervals, how many operations slipped, and the failures' causes.
Target: >= 99 % of 100 trials with detection on at P = 0.5, for house-roof, the five Panda
tasks, table-cleaning, stacking and the three iCub experiments.

    python benchmarks/bench_slips.py EXPERIMENT [EXPERIMENT ...] [--trials N] [--seed S]
                                     [--probability P] [--workers W] [--json]
"""

from __future__ import annotations

import argparse
import json
from collections import Counter

from vslsp.tasks import get_task, run_trials
from vslsp.tasks.statistics import wilson_interval


def slipped(results) -> int:
    """Operations of ``results`` in which the tutor slipped (their ``slip`` record; the iCub's
    demonstrated operations are its ``tutor_operations``, its ``operations`` the robot's steps)."""
    demonstrated = [op for r in results for op in r.details.get("tutor_operations", [])]
    return sum(1 for r in results for op in r.operations or [] if op.get("slip")) + sum(
        1 for op in demonstrated if op.get("slip", {}).get("applied")
    )


def measure(name: str, seeds: list[int], probability: float, detection: bool, workers: int) -> dict:
    task = get_task(name, tutor_slips=probability, slip_detection=detection)
    results = run_trials(task, seeds, workers=workers).results
    successes = sum(r.success for r in results)
    low, high = wilson_interval(successes, len(results))
    return {
        "experiment": name,
        "slip_detection": detection,
        "trials": len(results),
        "successes": successes,
        "rate": successes / len(results),
        "interval_95": [round(low, 3), round(high, 3)],
        "operations_slipped": slipped(results),
        "failures": dict(Counter(r.cause for r in results if not r.success)),
        "failed_seeds": [r.seed for r in results if not r.success],
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("experiments", nargs="+")
    parser.add_argument("--trials", type=int, default=100)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--probability", type=float, default=0.5)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    seeds = list(range(args.seed, args.seed + args.trials))
    rows = [
        measure(name, seeds, args.probability, detection, args.workers)
        for name in args.experiments
        for detection in (True, False)
    ]
    if args.json:
        print(json.dumps({"probability": args.probability, "seed": args.seed, "rows": rows}))
        return
    print(f"tutor slips P = {args.probability}, seeds {seeds[0]}-{seeds[-1]}")
    print(f"{'experiment':<22} {'detection':<9} {'success':>9} {'rate':>7} {'95 % interval':>15} {'slipped':>8}")
    for row in rows:
        low, high = row["interval_95"]
        print(
            f"{row['experiment']:<22} {'on' if row['slip_detection'] else 'off':<9} "
            f"{row['successes']:>4}/{row['trials']:<4} {100 * row['rate']:>6.1f}% "
            f"{100 * low:>6.1f}-{100 * high:<6.1f}% {row['operations_slipped']:>8}"
        )
        if row["failures"]:
            print(f"    failures: {row['failures']} (seeds {row['failed_seeds'][:12]})")
    for name in args.experiments:
        on, off = (next(r for r in rows if r["experiment"] == name and r["slip_detection"] is d) for d in (True, False))
        print(f"{name}: detection on {100 * on['rate']:.1f} % vs off {100 * off['rate']:.1f} % (target >= 99 % on)")


if __name__ == "__main__":
    main()
