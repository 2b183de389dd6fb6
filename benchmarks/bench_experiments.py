"""End-to-end benchmark: every registered experiment's cost per trial, success rates, and
`vslsp demo`'s time.

Cost (issue "Fast trials"): seconds per trial of every experiment, and that figure divided by a
fixed pybullet workload timed in the same process (a KUKA iiwa among cubes for a fixed number
of physics steps, plus a few 640x480 TinyRenderer views), so that figures compare across
machines and across loads of a shared machine. Trials run one after another in this process;
in wall-clock time each trial run is divided by the workload timed just before and after it, in
CPU time (the process and the planner it starts; hardly changed by other programs loading the
machine) by the workload's CPU time; each seed runs ``--repeat`` times and counts with its
quickest run. Target: each iCub experiment <= 1/3 of the
figure before the speed work (pull-in-order: 5.2-5.3 workloads per trial before).

Success (issue "VSL-SP end to end"): >= 99 % over 100 trials per experiment without faults,
>= 95 % with faults injected; `vslsp demo` cold start to finish <= 60 s on the 2-core machine.

    python benchmarks/bench_experiments.py [--speed-trials N] [--repeat R] [--trials N] [--workers W]
                                           [--no-speed] [--no-success] [--no-faults] [--no-demo] [--json]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time

import numpy as np
import pybullet_data

from vslsp.sim.quiet import quiet
from vslsp.tasks import Option, get_task, list_tasks, run_one, run_trials
from vslsp.tasks.base import cpu_seconds

with quiet():
    import pybullet as pb

TARGETS = {False: 0.99, True: 0.95}
WORKLOAD_STEPS = 2000
WORKLOAD_VIEWS = 4


def workload() -> tuple[float, float]:
    """Wall-clock and CPU seconds of the fixed pybullet workload: a KUKA iiwa swinging its joints among 12 cubes
    on a plane for :data:`WORKLOAD_STEPS` steps (240 Hz), then :data:`WORKLOAD_VIEWS` 640x480
    TinyRenderer views of the scene."""
    with quiet():
        client = pb.connect(pb.DIRECT)
    try:
        start, cpu = time.perf_counter(), cpu_seconds()
        pb.setAdditionalSearchPath(pybullet_data.getDataPath(), physicsClientId=client)
        pb.setGravity(0, 0, -9.81, physicsClientId=client)
        pb.setPhysicsEngineParameter(deterministicOverlappingPairs=1, physicsClientId=client)
        pb.loadURDF("plane.urdf", physicsClientId=client)
        with quiet():
            arm = pb.loadURDF("kuka_iiwa/model.urdf", [0, 0, 0], useFixedBase=True, physicsClientId=client)
        box = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=[0.025] * 3, physicsClientId=client)
        look = pb.createVisualShape(
            pb.GEOM_BOX, halfExtents=[0.025] * 3, rgbaColor=[0.9, 0.4, 0.1, 1], physicsClientId=client
        )
        for k in range(12):
            angle = 2 * np.pi * k / 12
            pb.createMultiBody(
                0.1, box, look, [0.55 * np.cos(angle), 0.55 * np.sin(angle), 0.025], physicsClientId=client
            )
        joints = list(range(pb.getNumJoints(arm, physicsClientId=client)))
        for step in range(WORKLOAD_STEPS):
            if step % 10 == 0:
                phase = step / 240.0
                targets = [0.8 * np.sin(phase + j) for j in joints]
                pb.setJointMotorControlArray(
                    arm, joints, pb.POSITION_CONTROL, targetPositions=targets, physicsClientId=client
                )
            pb.stepSimulation(physicsClientId=client)
        projection = pb.computeProjectionMatrixFOV(60, 640 / 480, 0.05, 5.0)
        for k in range(WORKLOAD_VIEWS):
            angle = 2 * np.pi * k / WORKLOAD_VIEWS
            view = pb.computeViewMatrix([1.6 * np.cos(angle), 1.6 * np.sin(angle), 1.0], [0, 0, 0.3], [0, 0, 1])
            pb.getCameraImage(640, 480, view, projection, renderer=pb.ER_TINY_RENDERER, physicsClientId=client)
        return time.perf_counter() - start, cpu_seconds() - cpu
    finally:
        pb.disconnect(client)


def speed(experiments: list[str], trials: int, repeat: int, seed: int) -> tuple[dict, list]:
    """The workload's quickest wall-clock and CPU seconds and, per experiment, seconds per
    trial and workloads per trial, averaged over ``trials`` seeds.

    In wall-clock time every trial run is divided by the workload timed just before and just
    after it (the machine's speed at that time); in CPU time (this process and the planner it
    runs) by the workload's quickest CPU time. Each seed counts with its quickest of
    ``repeat`` runs."""
    before = workload()
    references = [before]
    rows = []
    for name in experiments:
        task = get_task(name)
        seconds, ratios, cpus, successes = [], [], [], 0
        for k in range(trials):
            runs = []
            for _ in range(repeat):
                cpu = cpu_seconds()
                trial = run_one(task, seed + k)
                cpu = cpu_seconds() - cpu
                after = workload()
                references.append(after)
                runs.append((trial.time_s, trial.time_s / (0.5 * (before[0] + after[0])), cpu))
                before = after
            successes += trial.success
            seconds.append(min(r[0] for r in runs))
            ratios.append(min(r[1] for r in runs))
            cpus.append(min(r[2] for r in runs))
        rows.append(
            {
                "experiment": name,
                "trials": trials,
                "repeat": repeat,
                "successes": successes,
                "s_per_trial": float(np.mean(seconds)),
                "workloads_per_trial": float(np.mean(ratios)),
                "cpu_s_per_trial": float(np.mean(cpus)),
                "s_per_seed": [round(s, 2) for s in seconds],
                "workloads_per_seed": [round(r, 2) for r in ratios],
            }
        )
    reference = {"wall_s": min(r[0] for r in references), "cpu_s": min(r[1] for r in references)}
    for row in rows:
        row["cpu_workloads_per_trial"] = row["cpu_s_per_trial"] / reference["cpu_s"]
    return reference, rows


def demo_time() -> tuple[float, int]:
    """Wall-clock seconds of `vslsp demo` in a fresh process (cold start), and its exit code."""
    with tempfile.TemporaryDirectory() as out:
        start = time.perf_counter()
        done = subprocess.run([sys.executable, "-m", "vslsp", "demo", "--out", out], capture_output=True, text=True)
        return time.perf_counter() - start, done.returncode


def success(experiments: list[str], trials: int, seed: int, workers: int, with_faults: bool) -> list[dict]:
    """Success rates over ``trials`` seeded trials per experiment (VSL-SP: with and without faults)."""
    rows = []
    for name in experiments:
        takes_faults = Option.FAULTS in type(get_task(name)).options
        for faults in [False, True] if with_faults and takes_faults else [False]:
            task = get_task(name, faults=faults)
            start = time.perf_counter()
            results = run_trials(task, range(seed, seed + trials), workers=workers).results
            wall, cpu = time.perf_counter() - start, sum(t.cpu_s for t in results)
            rate = sum(t.success for t in results) / len(results)
            matched = [how for t in results for how in t.details.get("matched_by", [])]
            rows.append(
                {
                    "experiment": name,
                    "faults": faults,
                    "trials": len(results),
                    "success_rate": rate,
                    "target": TARGETS[faults],
                    "met": rate >= TARGETS[faults],
                    "replans": sum(t.details.get("replans", 0) for t in results),
                    "failed_steps": sum(t.details.get("failed_steps", 0) for t in results),
                    "s_per_trial": float(np.mean([t.time_s for t in results])),
                    "wall_s": wall,
                    "cpu_s": cpu,
                    "matched_by_match": matched.count("match"),
                    "matched_by_symbol": matched.count("symbol"),
                    "failures": [(t.seed, t.error) for t in results if not t.success],
                }
            )
            row = rows[-1]
            share = f", match finding {row['matched_by_match']}/{len(matched)}" if matched else ""
            print(
                f"{name:16s} faults={str(faults):5s} {rate * 100:5.1f} % of {len(results)} "
                f"(target {TARGETS[faults] * 100:.0f} %: {'met' if row['met'] else 'MISSED'}), "
                f"{row['replans']} replans{share}, {row['s_per_trial']:.1f} s/trial, "
                f"wall {wall:.0f} s, CPU {cpu:.0f} s",
                flush=True,
            )
            for failed_seed, error in row["failures"][:5]:
                print(f"    seed {failed_seed}: {error}")
    if rows:
        wall, cpu = sum(r["wall_s"] for r in rows), sum(r["cpu_s"] for r in rows)
        print(
            f"all {sum(r['trials'] for r in rows)} trials: wall {wall / 60:.1f} min, CPU {cpu / 60:.1f} min "
            f"(= {cpu / 60 / workers:.1f} min on {workers} cores that nothing else uses)",
            flush=True,
        )
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--speed-trials", type=int, default=3, help="seeds per experiment for the cost figures")
    parser.add_argument("--repeat", type=int, default=1, help="runs per seed (the quickest counts)")
    parser.add_argument("--trials", type=int, default=100, help="trials per experiment for the success rates")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument(
        "--experiments",
        nargs="*",
        default=[cls.name for cls in list_tasks()],
        help="registered experiments (default: all; vslsp experiment --list)",
    )
    parser.add_argument("--no-speed", action="store_true", help="skip the cost figures")
    parser.add_argument("--no-success", action="store_true", help="only the cost figures")
    parser.add_argument("--no-faults", action="store_true", help="skip the fault-injected runs")
    parser.add_argument("--no-demo", action="store_true", help="skip timing `vslsp demo`")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()

    reference, cost = ({}, []) if args.no_speed else speed(args.experiments, args.speed_trials, args.repeat, args.seed)
    if reference:
        print(
            f"fixed workload (KUKA among cubes, {WORKLOAD_STEPS} steps + {WORKLOAD_VIEWS} 640x480 views): "
            f"{reference['wall_s']:.3f} s, {reference['cpu_s']:.3f} CPU s (quickest runs)"
        )
    for row in cost:
        print(
            f"{row['experiment']:16s} {row['s_per_trial']:6.2f} s/trial = {row['workloads_per_trial']:5.2f} wl; "
            f"{row['cpu_s_per_trial']:6.2f} CPU s/trial = {row['cpu_workloads_per_trial']:5.2f} workloads "
            f"({row['trials']} seeds x {row['repeat']} runs, {row['successes']}/{row['trials']} succeeded; "
            f"per seed {row['s_per_seed']} s, {row['workloads_per_seed']} workloads)",
            flush=True,
        )
    rates = (
        [] if args.no_success else success(args.experiments, args.trials, args.seed, args.workers, not args.no_faults)
    )
    seconds, code = (None, None) if args.no_demo else demo_time()
    if seconds is not None:
        print(
            f"vslsp demo cold start to finish: {seconds:.1f} s (exit {code}; target <= 60 s: "
            f"{'met' if seconds <= 60 and code == 0 else 'MISSED'}; {seconds / 60:.2f} of the budget)"
        )
    if args.json:
        print(json.dumps({"workload": reference, "cost": cost, "success": rates, "demo_s": seconds, "demo_exit": code}))


if __name__ == "__main__":
    main()
