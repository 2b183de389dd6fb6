"""Benchmark (issue 30, item 1): demonstrations in which the tutor also disturbs another object.

For each experiment named, the same seeded trials run twice with ``--tutor-slips P``: with the
slip detection on (every object that moved in an operation is found, the operated one told from
those disturbed) and off (the paper's VSL, which takes the change for the operation), so that
the gain is shown on the same demonstrations and new scenes. It prints, per experiment, the
success rates with their 95 % intervals, how many operations slipped, and the failures' causes.
Target: >= 99 % of 100 trials with detection on at P = 0.5, for house-roof, the five Panda
tasks, table-cleaning, stacking and the three iCub experiments.

    python benchmarks/bench_slips.py EXPERIMENT [EXPERIMENT ...] [--trials N] [--seed S]
                                     [--probability P] [--detection on off] [--workers W]
                                     [--chunk K] [--out FILE.jsonl] [--report-only] [--json]

The seeds run in rounds of ``--chunk``, each round every experiment with the detection on and
off, so that a run stopped early still compares the two on the same seeds; ``--out`` keeps the
trials (one JSON line each) and a later run with the same file runs only those missing, so the
100 trials of eleven experiments may be gathered over several runs or machines.
"""

from __future__ import annotations

import argparse
import json

from vslsp.tasks import get_task, run_trials, trial_log


def slipped(result) -> int:
    """Operations of ``result`` in which the tutor slipped (their ``slip`` record; the iCub's
    demonstrated operations are its ``tutor_operations``, its ``operations`` the robot's steps)."""
    demonstrated = result.details.get("tutor_operations", [])
    return sum(1 for op in result.operations or [] if op.get("slip")) + sum(
        1 for op in demonstrated if op.get("slip", {}).get("applied")
    )


def run(group: dict, seeds: list[int], workers: int) -> tuple[list[dict], bool]:
    """The trials of ``seeds`` of ``group`` (experiment, probability, slip_detection), one
    line each (those finished when Ctrl-C or SIGTERM stopped the run), and whether it was
    stopped."""
    task = get_task(group["experiment"], tutor_slips=group["probability"], slip_detection=group["slip_detection"])
    trials = run_trials(task, seeds, workers=workers)
    records = trial_log.trial_records(trials.results, **group)
    for record, result in zip(records, trials.results):
        record["slipped"] = slipped(result)
    return records, bool(trials.interrupted)


def row(records: list[dict]) -> dict:
    """Success, its 95 % interval, the operations slipped and the failures of ``records``."""
    return {**trial_log.success_row(records), "operations_slipped": sum(r.get("slipped", 0) for r in records)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("experiments", nargs="+")
    parser.add_argument("--trials", type=int, default=100)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--probability", type=float, default=0.5)
    parser.add_argument("--detection", nargs="+", default=["on", "off"], choices=["on", "off"])
    trial_log.add_arguments(parser, "experiment and detection")
    args = parser.parse_args()
    seeds = list(range(args.seed, args.seed + args.trials))
    groups = [
        {"experiment": name, "probability": args.probability, "slip_detection": d == "on"}
        for d in args.detection
        for name in args.experiments
    ]
    records = trial_log.gather(args, seeds, groups, run)
    report(records, args, seeds)


def report(records: list[dict], args: argparse.Namespace, seeds: list[int]) -> None:
    """Print (or with ``--json`` write) the rows of ``records`` on ``seeds``."""
    wanted = set(seeds)
    groups = {
        (name, detection): [
            r
            for r in trial_log.of(
                records, {"experiment": name, "probability": args.probability, "slip_detection": detection}
            )
            if r["seed"] in wanted
        ]
        for name in args.experiments
        for detection in (True, False)
    }
    rows = {key: row(group) for key, group in groups.items() if group}
    if not rows:
        raise SystemExit("no trials to report")
    if args.json:
        print(
            json.dumps(
                {
                    "probability": args.probability,
                    "seed": args.seed,
                    "rows": [{"experiment": n, "slip_detection": d, **r} for (n, d), r in rows.items()],
                }
            )
        )
        return
    covered = sorted({r["seed"] for group in groups.values() for r in group})
    print(f"tutor slips P = {args.probability}, {len(covered)} seeds from {covered[0]} to {covered[-1]}")
    print(f"{'experiment':<22} {'detection':<9} {'success':>9} {'rate':>7} {'95 % interval':>15} {'slipped':>8}")
    for (name, detection), data in rows.items():
        low, high = data["interval_95"]
        print(
            f"{name:<22} {'on' if detection else 'off':<9} "
            f"{data['successes']:>4}/{data['trials']:<4} {100 * data['rate']:>6.1f}% "
            f"{100 * low:>6.1f}-{100 * high:<6.1f}% {data['operations_slipped']:>8}"
        )
        for seed, error in data["failed"].items():
            print(f"    seed {seed}: {error}")
    for name in args.experiments:
        on, off = rows.get((name, True)), rows.get((name, False))
        if on and off:
            print(f"{name}: detection on {100 * on['rate']:.1f} % vs off {100 * off['rate']:.1f} % (target >= 99 % on)")


if __name__ == "__main__":
    main()
