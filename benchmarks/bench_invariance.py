"""Benchmark (issue 38): the paper's claims outside our own scenes. The paper says VSL "is
scale-invariant, color-invariant, and view-invariant" and names "the noise in the images and the
occlusion of the objects" as its failure factors; this runs each experiment that takes
``--perturb`` over the levels of each perturbation (the demonstration as recorded, the
reproduction's camera and scene changed) and prints success against level, with the unperturbed
rate beside it, and draws it (one panel per perturbation, one curve per experiment, the targets
and the paper's claim marked).

Levels (issue 38's "done when"): the camera moved 10 cm / 10 deg, scale 0.8x and 1.25x, brightness
40 %, colour temperature 3000 K and 8000 K, Gaussian noise sigma 8 grey levels, one object 25 %
occluded, two distractors, each alone; and half of each. Target: >= 95 % at the full levels and
>= 99 % at half, over 100 trials per experiment and level on seeds no rule came from.

    python benchmarks/bench_invariance.py [EXPERIMENT ...] [--trials N] [--seed S] [--kinds camera scale ...]
                                          [--half-only | --full-only] [--workers W] [--chunk K]
                                          [--out FILE.jsonl] [--report-only] [--figure FILE.png] [--json]

The default seeds, 7600000 onwards, are seeds no rule of vslsp was found on. Trials are kept as
JSON lines (``--out``) and a later run with the same file runs only those missing.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from vslsp.tasks import get_task, run_trials, trial_log

#: Each perturbation's levels: (half, full) of issue 38's "done when", as ``--perturb`` items.
LEVELS: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "camera": (("camera=5",), ("camera=10",)),
    "scale (nearer)": (("scale=1.12",), ("scale=1.25",)),
    "scale (farther)": (("scale=0.9",), ("scale=0.8",)),
    "brightness": (("brightness=20",), ("brightness=40",)),
    "warm light": (("temperature=4750",), ("temperature=3000",)),
    "cool light": (("temperature=7250",), ("temperature=8000",)),
    "noise": (("noise=4",), ("noise=8",)),
    "occlusion": (("occlusion=12.5",), ("occlusion=25",)),
    "clutter": (("clutter=1",), ("clutter=2",)),
}
#: What the paper claims of each perturbation (the figure's panel titles).
CLAIMS = {
    "camera": "view-invariant (claimed)",
    "scale (nearer)": "scale-invariant (claimed)",
    "scale (farther)": "scale-invariant (claimed)",
    "brightness": "colour-invariant (claimed)",
    "warm light": "colour-invariant (claimed)",
    "cool light": "colour-invariant (claimed)",
    "noise": "a failure factor (the paper)",
    "occlusion": "a failure factor (the paper)",
    "clutter": "not discussed",
}
FAMILIES = ("house-roof", "alphabet-ordering", "animal-puzzle", "tower-of-hanoi", "animals-vs-machines", "domino")
TARGETS = {"half": 0.99, "full": 0.95}


def run(group: dict, seeds: list[int], workers: int) -> tuple[list[dict], bool]:
    """The trials of ``seeds`` of ``group`` (experiment, kind, level, perturb), one line each."""
    items = tuple(group["perturb"].split()) if group["perturb"] else None
    task = get_task(group["experiment"], perturb=items)
    trials = run_trials(task, seeds, workers=workers)
    return trial_log.trial_records(trials.results, **group), bool(trials.interrupted)


def groups_of(experiments: list[str], kinds: list[str], which: tuple[str, ...]) -> list[dict]:
    """Every (experiment, kind, level) to run: level 0 once per experiment, then each kind's levels."""
    found = [{"experiment": name, "kind": "none", "level": "0", "perturb": ""} for name in experiments]
    for kind in kinds:
        half, full = LEVELS[kind]
        for level, items in (("half", half), ("full", full)):
            if level in which:
                found += [
                    {"experiment": n, "kind": kind, "level": level, "perturb": " ".join(items)} for n in experiments
                ]
    return found


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("experiments", nargs="*", default=list(FAMILIES))
    parser.add_argument("--trials", type=int, default=100)
    parser.add_argument("--seed", type=int, default=7_600_000)
    parser.add_argument("--kinds", nargs="+", default=list(LEVELS), choices=list(LEVELS))
    level = parser.add_mutually_exclusive_group()
    level.add_argument("--half-only", action="store_true")
    level.add_argument("--full-only", action="store_true")
    parser.add_argument("--figure", type=Path, default=None, help="draw success against level into this PNG")
    trial_log.add_arguments(parser, "experiment, perturbation and level")
    args = parser.parse_args()
    seeds = list(range(args.seed, args.seed + args.trials))
    which = ("half",) if args.half_only else ("full",) if args.full_only else ("half", "full")
    groups = groups_of(args.experiments, args.kinds, which)
    records = trial_log.gather(args, seeds, groups, run)
    rows = report(records, groups, seeds, args)
    if args.figure is not None:
        draw(rows, args.experiments, args.kinds, args.figure, seeds)


def report(records: list[dict], groups: list[dict], seeds: list[int], args: argparse.Namespace) -> list[dict]:
    """Print (or with ``--json`` write) each group's success row on ``seeds``; return the rows."""
    wanted = set(seeds)
    rows = []
    for group in groups:
        done = [r for r in trial_log.of(records, group) if r["seed"] in wanted]
        if done:
            rows.append({**group, **trial_log.success_row(done)})
    if not rows:
        raise SystemExit("no trials to report")
    if args.json:
        print(json.dumps({"seed": args.seed, "trials": args.trials, "rows": rows}))
        return rows
    print(f"seeds {seeds[0]}-{seeds[-1]} (no rule was found on them); targets: >= 99 % at half, >= 95 % at full")
    head = f"{'experiment':<20} {'perturbation':<16} {'level':<6} {'items':<18}"
    print(f"{head} {'success':>9} {'rate':>7} {'95 % interval':>15}")
    for row in rows:
        low, high = row["interval_95"]
        target = TARGETS.get(row["level"])
        mark = "" if target is None else ("  ok" if row["rate"] >= target else f"  below {100 * target:.0f} %")
        print(
            f"{row['experiment']:<20} {row['kind']:<16} {row['level']:<6} {row['perturb'] or '-':<18} "
            f"{row['successes']:>4}/{row['trials']:<4} {100 * row['rate']:>6.1f}% "
            f"{100 * low:>6.1f}-{100 * high:<6.1f}%{mark}"
        )
        for seed, error in list(row["failed"].items())[:5]:
            print(f"    seed {seed}: {error}")
    return rows


def draw(rows: list[dict], experiments: list[str], kinds: list[str], path: Path, seeds: list[int]) -> None:
    """Success against level (0, half, full), a panel per perturbation, a curve per experiment."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    columns = min(3, len(kinds))
    lines = (len(kinds) + columns - 1) // columns
    figure, axes = plt.subplots(lines, columns, figsize=(4.2 * columns, 3.2 * lines), squeeze=False)
    rate = {(r["experiment"], r["kind"], r["level"]): r["rate"] for r in rows}
    for panel, kind in zip(axes.flat, kinds):
        for name in experiments:
            points = [
                (x, rate.get((name, "none" if x == 0 else kind, level)))
                for x, level in ((0, "0"), (1, "half"), (2, "full"))
            ]
            xs, ys = (
                zip(*[(x, 100 * y) for x, y in points if y is not None])
                if any(y is not None for _, y in points)
                else ((), ())
            )
            panel.plot(xs, ys, marker="o", label=name)
        panel.plot([1, 2], [99, 95], "k:", marker="_", markersize=14, label="target")
        panel.set_xticks(
            [0, 1, 2], ["0", f"half\n{' '.join(LEVELS[kind][0])}", f"full\n{' '.join(LEVELS[kind][1])}"], fontsize=8
        )
        panel.set_ylim(0, 102)
        panel.set_ylabel("trials succeeded (%)")
        panel.set_title(f"{kind}: {CLAIMS[kind]}", fontsize=9)
    for panel in list(axes.flat)[len(kinds) :]:
        panel.axis("off")
    axes.flat[0].legend(fontsize=7, loc="lower left")
    figure.suptitle(f"VSL under perturbations of the reproduction's world (seeds {seeds[0]}-{seeds[-1]})", fontsize=11)
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    print(f"figure: {path}")


if __name__ == "__main__":
    main()
