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
                                     [--views 2 1] [--chunk K] [--out FILE.jsonl] [--json]

The seeds run in rounds of ``--chunk``, each round every experiment with every view count, so
that a run stopped early still compares the two on the same seeds; ``--out`` keeps the trials
and a later run with the same file runs only those missing.
"""

from __future__ import annotations

import argparse
import json
import statistics

from vslsp.tasks import get_task, run_trials, trial_log

EXPERIMENTS = ("table-cleaning", "stacking")


def run(group: dict, seeds: list[int], workers: int) -> tuple[list[dict], bool]:
    """The trials of ``seeds`` of ``group`` (experiment, views), one line each (those finished
    when Ctrl-C or SIGTERM stopped the run), and whether it was stopped."""
    trials = run_trials(get_task(group["experiment"], views=group["views"]), seeds, workers=workers)
    return trial_log.trial_records(trials.results, **group), bool(trials.interrupted)


def row(records: list[dict]) -> dict:
    """Success, its 95 % interval, the median CPU seconds and the failures of ``records``."""
    return {
        **trial_log.success_row(records),
        "median_cpu_s": round(statistics.median(r["cpu_s"] for r in records), 3),
    }


def cost_ratio(one: list[dict], two: list[dict]) -> dict:
    """Two views' cost against one's on the same seeds: the ratio of the medians per trial and
    the median of the per-seed ratios."""
    first = {r["seed"]: r["cpu_s"] for r in one}
    paired = [r["cpu_s"] / first[r["seed"]] for r in two if first.get(r["seed"], 0) > 0]
    return {
        "seeds": len(paired),
        "ratio_of_medians": round(row(two)["median_cpu_s"] / row(one)["median_cpu_s"], 3),
        "median_paired_ratio": round(statistics.median(paired), 3) if paired else None,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("experiments", nargs="*", default=list(EXPERIMENTS))
    parser.add_argument("--trials", type=int, default=50)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--views", type=int, nargs="+", default=[2, 1], choices=[1, 2])
    trial_log.add_arguments(parser, "experiment and view")
    args = parser.parse_args()
    seeds = list(range(args.seed, args.seed + args.trials))
    groups = [{"experiment": name, "views": views} for views in args.views for name in args.experiments]
    records = trial_log.gather(args, seeds, groups, run)
    report(records, args, seeds)


def report(records: list[dict], args: argparse.Namespace, seeds: list[int]) -> None:
    """Print (or with ``--json`` write) the rows and cost ratios of ``records`` on ``seeds``."""
    wanted = set(seeds)
    groups = {
        (name, views): [r for r in records if r["experiment"] == name and r["views"] == views and r["seed"] in wanted]
        for name in args.experiments
        for views in (1, 2)
    }
    rows = {key: row(group) for key, group in groups.items() if group}
    if not rows:
        raise SystemExit("no trials to report")
    ratios = {
        name: cost_ratio(groups[name, 1], groups[name, 2])
        for name in args.experiments
        if groups[name, 1] and groups[name, 2]
    }
    if args.json:
        print(
            json.dumps(
                {
                    "seed": args.seed,
                    "rows": [{"experiment": n, "views": v, **r} for (n, v), r in rows.items()],
                    "cost_ratio": ratios,
                }
            )
        )
        return
    covered = sorted({r["seed"] for group in groups.values() for r in group})
    print(f"VSL-3D with one and two depth cameras, {len(covered)} seeds from {covered[0]} to {covered[-1]}")
    print(f"{'experiment':<16} {'views':>5} {'success':>9} {'rate':>7} {'95 % interval':>15} {'cpu s/trial':>11}")
    for (name, views), data in rows.items():
        low, high = data["interval_95"]
        print(
            f"{name:<16} {views:>5} {data['successes']:>4}/{data['trials']:<4} {100 * data['rate']:>6.1f}% "
            f"{100 * low:>6.1f}-{100 * high:<6.1f}% {data['median_cpu_s']:>11}"
        )
        for seed, error in data["failed"].items():
            print(f"    seed {seed}: {error}")
    for name, ratio in ratios.items():
        print(
            f"{name}: two views cost {ratio['ratio_of_medians']}x one per trial (median of {ratio['seeds']} paired "
            f"ratios {ratio['median_paired_ratio']}x; target <= 1.5x)"
        )


if __name__ == "__main__":
    main()
