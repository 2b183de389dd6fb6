"""DMP benchmark: vslsp.dmp against movement_primitives (dfki-ric) on the same demonstrations.

Both learn one demonstration with 50 basis functions, α_z = 25, β_z = α_z / 4 and a phase that
decays to 0.01 over the movement, and roll out at the demonstration's sample period for their
own default length: ours 1.3 τ (the spring settles on the goal), theirs τ (their forcing term
is meant to end there; run longer, it pushes the hand off the goal before the spring returns).
Measured in the same run: fit time, one rollout, 1000 start/goal pairs (our one batched call
against a loop of their rollouts; target ≥ 50× faster), the reproduction RMSE on the
demonstration and the distance to 1000 new goals at the end of the rollout (target: within
0.5 mm of theirs). The demonstrations: a synthetic smooth reach, and the first recorded reach of
push and of pull in the shipped skill library (the tutor's kinesthetic teaching, object frame).

    .venv/bin/python benchmarks/bench_dmp.py [--pairs 1000] [--json results.json]
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np
import torch
from rich.console import Console
from rich.progress import track
from rich.table import Table

import movement_primitives
from movement_primitives.dmp import DMP as TheirDMP
from vslsp.dmp import DMP
from vslsp.skills import SkillLibrary, default_library_path

N_BASIS = 50
RUN = 1.3  # our default rollout: 1.3 τ
# Their default integrator (RK4, one step per sample) and their Euler with 1 ms steps, the
# scheme ours uses (semi-implicit Euler, τ / 1000 steps).
THEIRS = {"theirs RK4": "rk4-cython", "theirs Euler": "euler-cython"}
progress = Console(stderr=True)


def smooth_reach() -> tuple[np.ndarray, np.ndarray]:
    """1 s, 101 samples: minimum-jerk over 36 cm with a 10 cm lift, at rest at both ends."""
    t = np.linspace(0.0, 1.0, 101)
    jerk = 10 * t**3 - 15 * t**4 + 6 * t**5
    lift = np.sin(np.pi * t) ** 2
    return t, np.outer(jerk, [0.3, -0.2, 0.0]) + np.outer(lift, [0.05, 0.0, 0.1])


def demonstrations() -> dict[str, tuple[np.ndarray, np.ndarray]]:
    library = SkillLibrary.load(default_library_path())
    demos = {"smooth reach (synthetic)": smooth_reach()}
    for name in ("push", "pull"):
        t, y = library[name].demos[0]
        demos[f"{name} reach (tutor)"] = (t - t[0], y)
    return demos


def rmse(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.sum((a - b) ** 2, axis=-1))))


def timed(function, repeat: int = 1) -> tuple[float, object]:
    """The best of ``repeat`` wall-clock times (s), and the result."""
    best = np.inf
    for _ in range(repeat):
        start = time.perf_counter()
        result = function()
        best = min(best, time.perf_counter() - start)
    return best, result


def theirs_rollout(dmp: TheirDMP, start: np.ndarray, goal: np.ndarray, step_function: str) -> np.ndarray:
    """Their positions (T, D) from ``start`` to ``goal`` over their execution time."""
    dmp.configure(start_y=start, goal_y=goal)
    return dmp.open_loop(step_function=step_function)[1]


def measure_ours(t: np.ndarray, y: np.ndarray, starts: np.ndarray, goals: np.ndarray) -> dict:
    tau, dt = float(t[-1]), float(np.mean(np.diff(t)))
    dmp = DMP(3, n_basis=N_BASIS)
    fit, _ = timed(lambda: dmp.fit([(t, y)]), 3)  # includes a reproduction, for fit_rmse
    reproduction = dmp.rollout(y[0], y[-1], tau=tau, dt=dt, duration=tau).y[: len(y)]
    one, _ = timed(lambda: dmp.rollout(starts[0], goals[0], tau=tau, dt=dt, duration=RUN * tau), 5)
    batch, rollout = timed(lambda: dmp.rollout(starts, goals, tau=tau, dt=dt, duration=RUN * tau), 3)
    settled = dmp.rollout(starts, goals, tau=tau, dt=dt, duration=1.5 * tau).y[:, -1]
    return {"fit_ms": fit * 1e3, "rollout_ms": one * 1e3, "batch_s": batch,
            "reproduction_rmse_mm": rmse(reproduction, y) * 1e3,
            "goal_error_mean_mm": float(np.linalg.norm(rollout.y[:, -1] - goals, axis=1).mean() * 1e3),
            "goal_error_max_mm": float(np.linalg.norm(rollout.y[:, -1] - goals, axis=1).max() * 1e3),
            "goal_error_max_mm_at_1.5_tau": float(np.linalg.norm(settled - goals, axis=1).max() * 1e3)}


def measure_theirs(t: np.ndarray, y: np.ndarray, starts: np.ndarray, goals: np.ndarray, step_function: str) -> dict:
    tau, dt = float(t[-1]), float(np.mean(np.diff(t)))
    dmp = TheirDMP(3, execution_time=tau, dt=dt, n_weights_per_dim=N_BASIS)
    fit, _ = timed(lambda: dmp.imitate(t, y), 3)
    reproduction = theirs_rollout(dmp, y[0], y[-1], step_function)[: len(y)]
    one, _ = timed(lambda: theirs_rollout(dmp, starts[0], goals[0], step_function), 5)
    start = time.perf_counter()
    finals = np.array([
        theirs_rollout(dmp, s, g, step_function)[-1]
        for s, g in track(list(zip(starts, goals)), description=f"movement_primitives {step_function} x{len(goals)}",
                          console=progress, transient=True)
    ])
    loop = time.perf_counter() - start
    errors = np.linalg.norm(finals - goals, axis=1) * 1e3
    return {"fit_ms": fit * 1e3, "rollout_ms": one * 1e3, "batch_s": loop,
            "reproduction_rmse_mm": rmse(reproduction, y) * 1e3,
            "goal_error_mean_mm": float(errors.mean()), "goal_error_max_mm": float(errors.max())}


def compare(label: str, t: np.ndarray, y: np.ndarray, pairs: int) -> dict:
    rng = np.random.default_rng(0)
    starts = y[0] + rng.normal(0.0, 0.03, (pairs, 3))
    goals = y[-1] + rng.normal(0.0, 0.03, (pairs, 3))
    result = {"demonstration": label, "samples": len(t), "tau_s": float(t[-1]), "pairs": pairs,
              "ours": measure_ours(t, y, starts, goals)}
    for name, step_function in THEIRS.items():
        result[name] = measure_theirs(t, y, starts, goals, step_function)
    return result


def table(results: list[dict]) -> Table:
    device = DMP(1).device
    out = Table(title=f"vslsp.dmp (ours, torch on {device}, {torch.get_num_threads()} threads) vs "
                      f"movement_primitives {movement_primitives.__version__} (theirs); best of 3-5 runs, loops once")
    for column in ("demonstration", "measure", "ours", *THEIRS, "best theirs / ours"):
        out.add_column(column, justify="left" if column in ("demonstration", "measure") else "right")
    rows = [("fit", "fit_ms", "{:.1f} ms"), ("one rollout", "rollout_ms", "{:.2f} ms"),
            ("{pairs} rollouts: batch / loop", "batch_s", "{:.3f} s"),
            ("reproduction RMSE", "reproduction_rmse_mm", "{:.3f} mm"),
            ("goal error, mean", "goal_error_mean_mm", "{:.3f} mm"),
            ("goal error, max", "goal_error_max_mm", "{:.3f} mm")]
    for result in results:
        for k, (measure, key, fmt) in enumerate(rows):
            ours, theirs = result["ours"][key], [result[name][key] for name in THEIRS]
            best = min(theirs)
            ratio = f"{best / ours:,.1f}x" if key.endswith(("_ms", "_s")) else f"ours {ours - best:+.3f} mm"
            name = f"{result['demonstration']}, {result['samples']} samples" if k == 0 else ""
            out.add_row(name, measure.format(pairs=result["pairs"]), fmt.format(ours),
                        *(fmt.format(value) for value in theirs), ratio)
        out.add_section()
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, default=1000, help="start/goal pairs in the batch")
    parser.add_argument("--json", help="also write the figures to this JSON file")
    arguments = parser.parse_args()
    results = [compare(label, t, y, arguments.pairs) for label, (t, y) in demonstrations().items()]
    console = Console(width=120)
    console.print(table(results))
    speedups = [min(r[name]["batch_s"] for name in THEIRS) / r["ours"]["batch_s"] for r in results]
    console.print(f"batched rollout against the faster of their loops: {min(speedups):,.0f}x to "
                  f"{max(speedups):,.0f}x (target >= 50x: {'met' if min(speedups) >= 50 else 'MISSED'})")
    for key, what in [("reproduction_rmse_mm", "reproduction RMSE"), ("goal_error_max_mm", "goal error (max)")]:
        excess = max(r["ours"][key] - min(r[name][key] for name in THEIRS) for r in results)
        console.print(f"{what}, ours minus the better of theirs: at most {excess:+.3f} mm "
                      f"(target <= 0.5 mm: {'met' if excess <= 0.5 else 'MISSED'})")
    settled = max(r["ours"]["goal_error_max_mm_at_1.5_tau"] for r in results)
    console.print(f"ours, goal error (max) after 1.5 tau instead of 1.3 tau: {settled:.3f} mm")
    if arguments.json:
        with open(arguments.json, "w") as file:
            json.dump(results, file, indent=2)


if __name__ == "__main__":
    main()
