"""The VSL pick-and-place tasks as seeded, randomised trials (paper, "Simulation"; issue 6).

``house-roof``: each trial records the tutor's demonstration in a world built from the trial's
seed, builds a new world from the seed (bodies and roofs at random places and angles) and
reproduces the demonstration twice, with the fixed small pre-place frame and with the adaptive
one. A trial succeeds when the adaptive reproduction reaches the demonstrated goal on the
ground truth; the fixed frame's outcome is reported beside it.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

from vslsp.errors import InputError
from vslsp.parallel import run_jobs
from vslsp.vsl.house_roof import HouseRoofDemonstration, ObservationFeatures, Reproduction, demonstrate, reproduce
from vslsp.vsl.house_world import HouseWorld

TASKS = ("house-roof",  # the tabletop tasks' trials: vslsp.vsl.tabletop_report.run_trials
         "alphabet-ordering", "animal-puzzle", "tower-of-hanoi", "animals-vs-machines", "domino")
FRAMES = ("fixed", "adaptive")
REPRODUCTION_SEED = 1_000_003  # the reproduction world's seed is the trial's plus this


@dataclass
class HouseRoofTrial:
    """One trial: its seed, each frame policy's reproduction summary (``to_dict`` of
    :class:`Reproduction`), milliseconds per reproduction, and (when kept, for the report's
    figures) the demonstration and the reproductions themselves."""

    seed: int
    results: dict[str, dict]
    reproduction_ms: dict[str, float]
    time_s: float
    error: str | None = None
    demonstration: HouseRoofDemonstration | None = field(default=None, repr=False)
    reproductions: dict[str, Reproduction] = field(default_factory=dict, repr=False)

    @property
    def success(self) -> bool:
        return self.error is None and bool(self.results.get("adaptive", {}).get("success"))

    def to_dict(self) -> dict:
        return {"seed": self.seed, "success": self.success, "error": self.error, "time_s": round(self.time_s, 3),
                "reproduction_ms": {k: round(v, 1) for k, v in self.reproduction_ms.items()}, **self.results}


def run_trial(seed: int, keep: bool = False) -> HouseRoofTrial:
    """Demonstrate in the world of ``seed``, reproduce with both frame policies in the world of
    ``seed + REPRODUCTION_SEED``. ``keep`` holds on to the images for the report."""
    start = time.perf_counter()
    try:
        demo = demonstrate(seed)
    except InputError as error:  # the recorder could not see the tutor's operation
        return HouseRoofTrial(seed, {}, {}, time.perf_counter() - start, f"demonstration: {error}")
    features = ObservationFeatures(demo)
    world = HouseWorld.random(seed + REPRODUCTION_SEED)
    results, milliseconds, reproductions = {}, {}, {}
    for frame in FRAMES:
        clock = time.perf_counter()
        reproduction = reproduce(demo, world, frame, features)
        milliseconds[frame] = 1000.0 * (time.perf_counter() - clock)
        results[frame] = reproduction.to_dict()
        if keep:
            reproductions[frame] = reproduction
    return HouseRoofTrial(seed, results, milliseconds, time.perf_counter() - start, None,
                          demo if keep else None, reproductions)


def run_trials(trials: int, seed: int = 0, workers: int = 1, on_done=None) -> list[HouseRoofTrial]:
    """``trials`` trials with seeds ``seed``, ``seed + 1``, ... on ``workers`` processes, in seed
    order; ``on_done(trial)`` is called as each comes back (progress)."""
    check_counts(trials, workers)
    return run_jobs(run_trial, [seed + k for k in range(trials)], workers, on_done)


def check_counts(trials: int, workers: int) -> None:
    """--trials and --workers must be at least 1 (an InputError otherwise)."""
    if trials < 1:
        raise InputError(f"--trials must be at least 1, got {trials}")
    if workers < 1:
        raise InputError(f"--workers must be at least 1, got {workers}")


def summary(trials: list[HouseRoofTrial], seed: int) -> dict:
    """The JSON summary (DESIGN.md's ``vslsp experiment --json`` object, plus per-frame rates,
    per-operation rates, ms per reproduction and the failures)."""
    total = len(trials)
    data: dict = {"experiment": "house-roof", "trials": total, "seed": seed,
                  "successes": sum(t.success for t in trials)}
    data["success_rate"] = data["successes"] / total if total else 0.0
    for frame in FRAMES:
        done = [t for t in trials if frame in t.results]
        operations = [op for t in done for op in t.results[frame]["operations"]]
        successes = sum(t.results[frame]["success"] for t in done)
        times = [t.reproduction_ms[frame] for t in done]
        data[f"{frame}_frame"] = {
            "successes": successes, "success_rate": successes / total if total else 0.0,
            "operations": len(operations), "operations_ok": sum(op["diagnosis"] == "ok" for op in operations),
            "diagnoses": {d: sum(op["diagnosis"] == d for op in operations)
                          for d in sorted({op["diagnosis"] for op in operations})},
            "ms_per_reproduction": round(sum(times) / len(times), 1) if times else None,
        }
    data["failures"] = [{"seed": t.seed, "error": t.error or _failure(t)} for t in trials if not t.success]
    return data


def _failure(trial: HouseRoofTrial) -> str:
    """Which operations of the adaptive reproduction failed, and why."""
    operations = trial.results["adaptive"]["operations"]
    return "; ".join(f"operation {i}: {op['diagnosis']}" for i, op in enumerate(operations, start=1)
                     if op["diagnosis"] != "ok") or "goal not reached"
