"""End-to-end benchmark: the three VSL-SP experiments' success rates, and `vslsp demo`'s time.

Targets (issue "VSL-SP end to end"): success >= 99 % over 100 trials per experiment without
faults, >= 95 % with faults injected; `vslsp demo` cold start to finish <= 60 s on the 2-core
machine. Reference measured in the same run: one bare skill execution (DMP rollout, IK, physics,
no perception, no planning), so that a trial's time reads as "so many skill executions".

    python benchmarks/bench_experiments.py [--trials N] [--workers W] [--json]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from vslsp.loop.experiments import EXPERIMENTS, run_trials
from vslsp.sim import SceneSpec, World
from vslsp.skills import SkillLibrary, default_library_path
from vslsp.skills.execute import execute_skill

TARGETS = {False: 0.99, True: 0.95}


def skill_time(library: SkillLibrary, repeat: int = 3) -> float:
    """Seconds per bare pull execution (the reference)."""
    times = []
    for seed in range(repeat):
        spec = SceneSpec.random(seed, n_cubes=1, far=(True,))
        with World(spec) as world:
            x, y, _ = world.cube_pose(spec.cubes[0].name)
            start = time.perf_counter()
            execute_skill(world, library["pull"], np.array([x, y]), spec.landmark.normal)
            times.append(time.perf_counter() - start)
    return float(np.median(times))


def demo_time() -> tuple[float, int]:
    """Wall-clock seconds of `vslsp demo` in a fresh process (cold start), and its exit code."""
    with tempfile.TemporaryDirectory() as out:
        start = time.perf_counter()
        done = subprocess.run([sys.executable, "-m", "vslsp", "demo", "--out", out], capture_output=True, text=True)
        return time.perf_counter() - start, done.returncode


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=100)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--experiments", nargs="*", default=list(EXPERIMENTS))
    parser.add_argument("--no-faults", action="store_true", help="skip the fault-injected runs")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()

    library_path = default_library_path()
    reference = skill_time(SkillLibrary.load(library_path))
    seconds, code = demo_time()
    rows = []
    for name in args.experiments:
        for faults in ([False] if args.no_faults else [False, True]):
            start = time.perf_counter()
            trials = run_trials(name, args.trials, args.seed, library_path, workers=args.workers, faults=faults)
            wall = time.perf_counter() - start
            rate = sum(t.success for t in trials) / len(trials)
            rows.append({
                "experiment": name, "faults": faults, "trials": len(trials), "success_rate": rate,
                "target": TARGETS[faults], "met": rate >= TARGETS[faults],
                "replans": sum(t.replans for t in trials), "failed_steps": sum(t.failed_steps for t in trials),
                "s_per_trial": float(np.mean([t.time_s for t in trials])),
                "trial_in_skill_executions": float(np.mean([t.time_s for t in trials])) / reference,
                "wall_s": wall, "failures": [(t.seed, t.error) for t in trials if not t.success],
            })
            print(f"{name:16s} faults={str(faults):5s} {rate * 100:5.1f} % of {len(trials)} "
                  f"(target {TARGETS[faults] * 100:.0f} %: {'met' if rate >= TARGETS[faults] else 'MISSED'}), "
                  f"{rows[-1]['replans']} replans, {rows[-1]['s_per_trial']:.1f} s/trial "
                  f"= {rows[-1]['trial_in_skill_executions']:.1f} bare skill executions", flush=True)
            for seed, error in rows[-1]["failures"][:5]:
                print(f"    seed {seed}: {error}")
    print(f"reference: one bare pull execution {reference:.2f} s")
    print(f"vslsp demo cold start to finish: {seconds:.1f} s (exit {code}; target <= 60 s: "
          f"{'met' if seconds <= 60 and code == 0 else 'MISSED'}; {seconds / 60:.2f} of the budget)")
    if args.json:
        print(json.dumps({"reference_skill_s": reference, "demo_s": seconds, "demo_exit": code, "rows": rows}))


if __name__ == "__main__":
    main()
