"""Where a trial's CPU time goes, per experiment family, against the simulator's own floor
(issue "Trials at the simulator's own speed").

For each family (``vslsp experiment --list``) a fresh worker process runs N seeded trials one
after another, as ``vslsp experiment NAME --trials N --seed S`` does with one worker (the first
trial keeping its artefacts when the task asks for it, then the report and its figures), and
charges its CPU seconds (the process's and its children's: the planner) to stages:

- ``physics``: pybullet's ``stepSimulation``;
- ``rendering``: pybullet's ``getCameraImage``;
- ``matching``: OpenCV's SIFT (detect, compute) and matching calls (``BFMatcher`` and FLANN
  ``match``/``knnMatch``, ``estimateAffinePartial2D``/``estimateAffine2D``/``findHomography``,
  ``matchTemplate``);
- ``perception``, ``planning``, ``execution``: the rest of what the project's own stages
  (:mod:`vslsp.stages`) enclose; the planner's process counts as planning;
- ``report figures``: ``write_report`` (the summary and the figures, a trial it re-runs
  included);
- ``start-up``: the worker's CPU before its first trial (interpreter, imports, the task built)
  and every import made later;
- ``other``: the rest of the trials (building the scenes, the tutor, bookkeeping).

Each stage is charged its own time less that of the stages it encloses (the innermost one
counts). The hooks only time calls (nothing about the trial changes: its records are those of
``vslsp experiment``).

The FLOOR of a trial is measured in the same run: when a trial's pybullet client is about to
disconnect, the same number of ``stepSimulation`` calls and the same ``getCameraImage`` calls
(sizes, cameras, renderer) are replayed on that client's scene as the trial left it, with
nothing else; their CPU time is the floor and is not charged to the trial. Per family the
table gives the median CPU seconds of a trial, the median floor, the median of the per-trial
ratios (n/a for a family that runs no pybullet: house-roof's 2-D board), the whole run's CPU
per trial (start-up and report included) and each stage's share of the whole run's CPU.

    python benchmarks/bench_trial_cost.py [--families NAME ...] [--trials N] [--seed S]
                                          [--no-report] [--profile TOP] [--json FILE]

Seeds default to 7400000.. (nobody tuned on them). ``--profile TOP`` also prints each family's
TOP functions by cumulative time under cProfile (slower; for finding the waste, not for the
figures).
"""

from __future__ import annotations

import argparse
import builtins
import contextlib
import functools
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

SEED = 7_400_000
STAGES = (
    "physics",
    "rendering",
    "matching",
    "perception",
    "planning",
    "execution",
    "report figures",
    "start-up",
    "other",
)
MATCH_FUNCTIONS = ("estimateAffinePartial2D", "estimateAffine2D", "findHomography", "matchTemplate")
MATCHER_METHODS = ("match", "knnMatch", "radiusMatch")
SIFT_METHODS = ("detect", "compute", "detectAndCompute")


def children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def clock() -> float:
    """CPU seconds of this process and its finished children."""
    return time.process_time() + children_cpu()


class Meter:
    """CPU seconds charged to :data:`STAGES`, the innermost open stage counting; and, per
    pybullet client, the steps and camera images to replay as the floor."""

    def __init__(self) -> None:
        self.totals = dict.fromkeys(STAGES, 0.0)
        self.open: list[list[float]] = []  # per open stage: [start, nested time]
        self.sealed = 0  # inside report figures: everything is charged to it, nothing recorded
        self.steps: dict[int, int] = {}
        self.renders: dict[int, list[tuple[tuple, dict]]] = {}
        self.floor = 0.0
        self.floor_steps = 0
        self.floor_renders = 0

    @contextlib.contextmanager
    def charge(self, name: str, now: Callable[[], float] = clock) -> Iterator[None]:
        if self.sealed and name != "report figures":
            yield
            return
        start = now()
        self.open.append([start, 0.0])
        try:
            yield
        finally:
            elapsed = now() - start
            _, nested = self.open.pop()
            self.totals[name] += elapsed - nested
            if self.open:
                self.open[-1][1] += elapsed

    def timed(self, name: str, function: Callable) -> Callable:
        """``function`` with each call charged to ``name`` (process CPU only: no child ends in it)."""

        @functools.wraps(function)
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            with self.charge(name, time.process_time):
                return function(*args, **kwargs)

        return wrapper

    def replay(self, pb: Any, original: dict[str, Callable], client: int) -> None:
        """The floor: the client's steps and camera images again, on its scene as it is now."""
        steps, renders = self.steps.pop(client, 0), self.renders.pop(client, [])
        start = time.process_time()
        for _ in range(steps):
            original["stepSimulation"](physicsClientId=client)
        for args, kwargs in renders:
            original["getCameraImage"](*args, **kwargs)
        elapsed = time.process_time() - start
        self.floor += elapsed
        self.floor_steps += steps
        self.floor_renders += len(renders)
        for frame in self.open:  # the replay is no stage's time
            frame[0] += elapsed


class _Proxy:
    """An OpenCV object whose ``methods`` are charged to ``matching``."""

    def __init__(self, inner: Any, methods: tuple[str, ...], meter: Meter) -> None:
        self._inner, self._methods, self._meter = inner, methods, meter

    def __getattr__(self, name: str) -> Any:
        value = getattr(self._inner, name)
        return self._meter.timed("matching", value) if name in self._methods else value


def _proxied(make: Callable, methods: tuple[str, ...], meter: Meter) -> Callable:
    """``make`` (an OpenCV constructor) whose objects are :class:`_Proxy` ones."""

    def made(*args: Any, **kwargs: Any) -> _Proxy:
        return _Proxy(make(*args, **kwargs), methods, meter)

    return made


def install(meter: Meter) -> None:
    """Hook pybullet, OpenCV, the project's stages and imports into ``meter`` (before the
    project imports them: the SIFT detector is made once and kept)."""
    import cv2

    from vslsp import stages
    from vslsp.sim.quiet import quiet

    with quiet():
        import pybullet as pb

    original = {name: getattr(pb, name) for name in ("stepSimulation", "getCameraImage", "disconnect")}
    step = meter.timed("physics", original["stepSimulation"])
    render = meter.timed("rendering", original["getCameraImage"])

    def client_of(args: tuple, kwargs: dict, position: int) -> int:
        return int(kwargs.get("physicsClientId", args[position] if len(args) > position else 0))

    def step_simulation(*args: Any, **kwargs: Any) -> Any:
        if not meter.sealed:
            client = client_of(args, kwargs, 0)
            meter.steps[client] = meter.steps.get(client, 0) + 1
        return step(*args, **kwargs)

    def get_camera_image(*args: Any, **kwargs: Any) -> Any:
        if not meter.sealed:
            meter.renders.setdefault(client_of(args, kwargs, 99), []).append((args, kwargs))
        return render(*args, **kwargs)

    def disconnect(*args: Any, **kwargs: Any) -> Any:
        client = client_of(args, kwargs, 0)
        if client in meter.steps or client in meter.renders:
            meter.replay(pb, original, client)
        return original["disconnect"](*args, **kwargs)

    pb.stepSimulation, pb.getCameraImage, pb.disconnect = step_simulation, get_camera_image, disconnect

    for name in MATCH_FUNCTIONS:
        setattr(cv2, name, meter.timed("matching", getattr(cv2, name)))
    for name, methods in (
        ("SIFT_create", SIFT_METHODS),
        ("BFMatcher", MATCHER_METHODS),
        ("BFMatcher_create", MATCHER_METHODS),
        ("FlannBasedMatcher", MATCHER_METHODS),
    ):
        setattr(cv2, name, _proxied(getattr(cv2, name), methods, meter))

    # vslsp.stages.stage is a contextmanager: its helper calls the generator function it closes
    # over, so swapping that one cell reaches every module that imported ``stage`` by name.
    cell = next(c for c in stages.stage.__closure__ or () if c.cell_contents is stages.stage.__wrapped__)
    inner = cell.cell_contents

    def metered(name: str) -> Iterator[None]:
        with meter.charge(name):
            yield from inner(name)

    cell.cell_contents = metered

    real_import = builtins.__import__

    def charged_import(*args: Any, **kwargs: Any) -> Any:
        with meter.charge("start-up"):
            return real_import(*args, **kwargs)

    builtins.__import__ = charged_import


def worker(name: str, seeds: list[int], report: bool, profile: int) -> dict:
    """Run ``name``'s trials in this (fresh) process, metered; the figures as a dict."""
    meter = Meter()
    install(meter)
    from vslsp.tasks import get_task, run_one
    from vslsp.tasks.records import without_times
    from vslsp.tasks.report import write_report
    from vslsp.tasks.runner import Run

    task = get_task(name)
    usage = resource.getrusage(resource.RUSAGE_SELF)
    meter.totals["start-up"] = usage.ru_utime + usage.ru_stime  # since exec: all before the first trial
    profiler = None
    if profile:
        import cProfile

        profiler = cProfile.Profile()
        profiler.enable()
    trials, results = [], []
    for k, seed in enumerate(seeds):
        before = dict(meter.totals)
        floor, steps, renders = meter.floor, meter.floor_steps, meter.floor_renders
        start = clock()
        result = run_one(task, seed, keep=k == 0 and task.keep_first)
        cpu = clock() - start - (meter.floor - floor)
        charged = {stage: meter.totals[stage] - before[stage] for stage in STAGES}
        meter.totals["other"] += cpu - sum(charged.values())
        charged["other"] = meter.totals["other"] - before["other"]
        results.append(result)
        trials.append(
            {
                "seed": seed,
                "success": result.success,
                "cpu_s": cpu,
                "floor_s": meter.floor - floor,
                "steps": meter.floor_steps - steps,
                "renders": meter.floor_renders - renders,
                "unreplayed_steps": sum(meter.steps.values()),
                "stages_s": charged,
                "record": without_times(result.to_dict()),  # what the same seed must give again
            }
        )
    if report:
        with tempfile.TemporaryDirectory() as folder:
            meter.sealed += 1
            with meter.charge("report figures"):
                write_report(folder, task, Run(results, seeds))
            meter.sealed -= 1
    top = []
    if profiler is not None:
        import pstats

        profiler.disable()
        stats = pstats.Stats(profiler)
        rows = sorted(stats.stats.items(), key=lambda item: -item[1][3])[:profile]  # type: ignore[attr-defined]
        top = [
            {"function": f"{Path(file).name}:{line}:{function}", "calls": calls, "cumulative_s": round(cumulative, 3)}
            for (file, line, function), (_, calls, _, cumulative, _) in rows
        ]
    return {"experiment": name, "trials": trials, "totals_s": meter.totals, "profile": top}


def summarise(data: dict) -> dict:
    trials = data["trials"]
    run_cpu = sum(data["totals_s"].values())
    return {
        "experiment": data["experiment"],
        "seeds": [t["seed"] for t in trials],
        "successes": sum(t["success"] for t in trials),
        "cpu_s_per_trial": statistics.median(t["cpu_s"] for t in trials),
        "floor_s": statistics.median(t["floor_s"] for t in trials),
        # None: the family steps and renders nothing in pybullet (house-roof's board is 2-D)
        "ratio": statistics.median(t["cpu_s"] / t["floor_s"] for t in trials)
        if all(t["floor_s"] > 0 for t in trials)
        else None,
        "run_cpu_s_per_trial": run_cpu / len(trials),
        "steps_per_trial": statistics.median(t["steps"] for t in trials),
        "renders_per_trial": statistics.median(t["renders"] for t in trials),
        "unreplayed_steps": trials[-1]["unreplayed_steps"],
        "shares": {stage: data["totals_s"][stage] / run_cpu for stage in STAGES},
        "totals_s": data["totals_s"],
        "trials": trials,
        "profile": data["profile"],
    }


def run_family(name: str, seeds: list[int], report: bool, profile: int) -> dict:
    """One family in a fresh worker process (its own start-up, nothing imported before)."""
    command = [sys.executable, str(Path(__file__).resolve()), "--worker", name, "--seed", str(seeds[0])]
    command += ["--trials", str(len(seeds)), "--profile", str(profile)] + ([] if report else ["--no-report"])
    env = dict(os.environ, OMP_NUM_THREADS=os.environ.get("OMP_NUM_THREADS", "1"))
    done = subprocess.run(command, capture_output=True, text=True, env=env, check=False)
    if done.returncode != 0:
        raise SystemExit(f"{name}: the worker failed (exit {done.returncode}):\n{done.stderr[-3000:]}")
    return summarise(json.loads(done.stdout.strip().splitlines()[-1]))


def table(rows: list[dict]) -> list[str]:
    short = {"report figures": "report", "start-up": "start"}
    head = f"{'experiment':21s} {'ok':>5s} {'CPU s':>6s} {'floor':>6s} {'ratio':>6s} {'run/tr':>6s} "
    head += " ".join(f"{short.get(s, s)[:7]:>7s}" for s in STAGES)
    lines = [head]
    for row in rows:
        line = f"{row['experiment']:21s} {row['successes']:2d}/{len(row['seeds']):<2d} {row['cpu_s_per_trial']:6.2f} "
        ratio = "   n/a" if row["ratio"] is None else f"{row['ratio']:6.2f}"
        line += f"{row['floor_s']:6.2f} {ratio} {row['run_cpu_s_per_trial']:6.2f} "
        line += " ".join(f"{100 * row['shares'][s]:6.1f}%" for s in STAGES)
        lines.append(line)
    return lines


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--families", nargs="*", default=None, help="experiments (default: all)")
    parser.add_argument("--trials", type=int, default=10, help="seeded trials per family (default 10)")
    parser.add_argument("--seed", type=int, default=SEED, help=f"first seed (default {SEED})")
    parser.add_argument("--no-report", action="store_true", help="skip the report and its figures")
    parser.add_argument("--profile", type=int, default=0, metavar="TOP", help="also print TOP cProfile functions")
    parser.add_argument("--json", type=Path, default=None, metavar="FILE", help="write the figures as JSON")
    parser.add_argument("--worker", default=None, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.trials < 1:
        parser.error("--trials must be at least 1")
    seeds = list(range(args.seed, args.seed + args.trials))
    if args.worker is not None:
        data = worker(args.worker, seeds, not args.no_report, args.profile)
        sys.stdout.write("\n" + json.dumps(data) + "\n")
        return
    from vslsp.tasks import list_tasks

    names = [cls.name for cls in list_tasks()]
    families = args.families if args.families else names
    unknown = sorted(set(families) - set(names))
    if unknown:
        parser.error(f"unknown experiment(s) {', '.join(unknown)}; vslsp experiment --list names them")
    print(f"seeds {seeds[0]}..{seeds[-1]}; CPU s: median of a trial; floor: its own steps and renders replayed")
    rows = []
    print(table([])[0], flush=True)
    for name in families:
        started = time.perf_counter()
        rows.append(run_family(name, seeds, not args.no_report, args.profile))
        row = rows[-1]
        print(table([row])[1], flush=True)
        print(
            f"    {row['steps_per_trial']:.0f} steps, {row['renders_per_trial']:.0f} renders a trial; "
            f"{time.perf_counter() - started:.0f} s wall",
            flush=True,
        )
        for entry in row["profile"]:
            print(f"      {entry['cumulative_s']:8.2f} s {entry['calls']:8d}x {entry['function']}")
    print("\n".join(table(rows)))
    if args.json is not None:
        args.json.write_text(json.dumps({"seeds": seeds, "stages": list(STAGES), "families": rows}, indent=1) + "\n")


if __name__ == "__main__":
    main()
