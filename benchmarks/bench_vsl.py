"""VSL pick-and-place benchmark: the house-roof simulation's success over randomised trials.

Targets (issue 6): >= 99 % of pick-and-place operations succeed over 100 randomised trials
with the adaptive frame (the paper reports < 5 % failed operations); the fixed small frame is
the reference that shows why the adaptive frame is needed (the paper's wrong reproduction).
Also: ms per reproduction (three operations, each two SIFT extractions of the 960x720 world,
the pick and place matches and the trajectory) against ms per SIFT extraction of that world,
both measured in this process on a few trials (``--timing``), so the ratio reads on any
machine; the success rates come from the trials on ``--workers`` processes.

    python benchmarks/bench_vsl.py [--trials N] [--seed S] [--workers W] [--timing K] [--json]
    python benchmarks/bench_vsl.py --task NAME [--trials N] [--seed S] [--workers W] [--json]

``--task`` runs one of the five real-world tasks in the tabletop world instead (paper, "Real-
world Experiments"; alphabet-ordering, animal-puzzle, tower-of-hanoi, animals-vs-machines,
domino, or ``all``): the success rate of the robot's pick-and-place operations over randomised
trials (target >= 99 %), their diagnoses, trials reaching the goal, and seconds per trial (one
demonstration and one reproduction with the Panda in pybullet, on one core).

A trial (demonstration and two reproductions) costs about 3 s on one core of the 2-core
development machine: 100 trials took 333 s wall with 2 workers while other jobs loaded the
machine (about 150 s when idle).
"""

from __future__ import annotations

import argparse
import json
import time

from vslsp.vsl.tasks import FRAMES, run_trials, summary

from vslsp.vision.features import extract_features
from vslsp.worlds.house_roof.board import HouseWorld

OPERATION_TARGET = 0.99


def sift_ms(repeat: int = 5) -> float:
    """ms per SIFT extraction of a house-roof world image (the reference)."""
    image = HouseWorld.random(0).render()
    extract_features(image)
    start = time.perf_counter()
    for _ in range(repeat):
        extract_features(image)
    return 1000.0 * (time.perf_counter() - start) / repeat


def tabletop(names: list[str], trials: int, seed: int, workers: int, as_json: bool) -> None:
    """The real-world tasks' figures (see the module docstring)."""
    from vslsp.vsl.tabletop_report import run_trials as run_tabletop
    from vslsp.vsl.tabletop_report import summary as tabletop_summary

    figures = {}
    for name in names:
        start = time.perf_counter()
        data = tabletop_summary(name, run_tabletop(name, trials, seed, workers), seed)
        figures[name] = {
            key: data[key]
            for key in (
                "trials",
                "successes",
                "operations",
                "operations_ok",
                "operation_success_rate",
                "diagnoses",
                "s_per_trial",
                "failures",
            )
        }
        figures[name]["wall_s"] = round(time.perf_counter() - start, 1)
        figures[name]["operation_target_met"] = data["operation_success_rate"] >= OPERATION_TARGET
        if "intervention" in data:
            figures[name]["intervention"] = data["intervention"]
        if not as_json:
            f = figures[name]
            print(
                f"{name}: {f['trials']} trials from seed {seed}, {workers} workers, {f['wall_s']:.0f} s wall; "
                f"robot operations {f['operations_ok']}/{f['operations']} "
                f"({100 * f['operation_success_rate']:.1f} %, target >= {100 * OPERATION_TARGET:.0f} %: "
                f"{'met' if f['operation_target_met'] else 'NOT met'}) {f['diagnoses']}; goal reached in "
                f"{f['successes']}/{f['trials']} trials; {f['s_per_trial']} s per trial (one core)"
            )
            for failure in f["failures"][:10]:
                print(f"  seed {failure['seed']}: {failure['error']}")
    if as_json:
        print(json.dumps(figures))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--trials", type=int, default=100)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--timing", type=int, default=5, help="trials timed in this process")
    parser.add_argument("--json", action="store_true", help="print the figures as one JSON object")
    parser.add_argument("--task", default="house-roof", help="house-roof, a tabletop task, or all (tabletop)")
    args = parser.parse_args()
    if args.task != "house-roof":
        from vslsp.experiments.tabletop import TabletopExperiment
        from vslsp.tasks import list_tasks

        names = [cls.name for cls in list_tasks() if issubclass(cls, TabletopExperiment)]
        tabletop(names if args.task == "all" else [args.task], args.trials, args.seed, args.workers, args.json)
        return
    reference = sift_ms()
    timed = summary(run_trials(args.timing, args.seed), args.seed)
    start = time.perf_counter()
    trials = run_trials(args.trials, args.seed, args.workers)
    wall = time.perf_counter() - start
    data = summary(trials, args.seed)
    figures = {"trials": data["trials"], "wall_s": round(wall, 1), "sift_ms": round(reference, 1)}
    for frame in FRAMES:
        f = data[f"{frame}_frame"]
        figures[frame] = {
            "success_rate": f["success_rate"],
            "operation_success_rate": f["operations_ok"] / f["operations"] if f["operations"] else 0.0,
            "diagnoses": f["diagnoses"],
            "ms_per_reproduction": timed[f"{frame}_frame"]["ms_per_reproduction"],
            "reproduction_in_sift_extractions": round(timed[f"{frame}_frame"]["ms_per_reproduction"] / reference, 1),
        }
    figures["operation_target_met"] = figures["adaptive"]["operation_success_rate"] >= OPERATION_TARGET
    figures["failures"] = data["failures"]
    if args.json:
        print(json.dumps(figures))
        return
    print(f"house-roof, {data['trials']} trials from seed {args.seed}, {args.workers} workers, {wall:.0f} s wall")
    print(f"reference: SIFT on a 960x720 world image {reference:.0f} ms")
    for frame in FRAMES:
        f = figures[frame]
        print(
            f"  {frame:8s} frame: trials {100 * f['success_rate']:5.1f} %, operations "
            f"{100 * f['operation_success_rate']:5.1f} % {f['diagnoses']}, "
            f"{f['ms_per_reproduction']:.0f} ms per reproduction ({args.timing} trials in this process) "
            f"(= {f['reproduction_in_sift_extractions']} SIFT extractions)"
        )
    verdict = "met" if figures["operation_target_met"] else "NOT met"
    print(f"target >= {100 * OPERATION_TARGET:.0f} % of operations with the adaptive frame: {verdict}")
    for failure in data["failures"][:10]:
        print(f"  seed {failure['seed']}: {failure['error']}")


if __name__ == "__main__":
    main()
