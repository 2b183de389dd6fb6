"""The paper's three iCub experiments of VSL-SP as registered tasks (paper, VSL-SP "Results").

- ``simple-vsl-task``: three objects, one demonstrated sequence, reproduced by VSL's own
  planner (match finding with adaptive frames, no PDDL) in a reshuffled scene;
- ``keep-all-near``: three demonstrations teach the rule "no block is far", which then solves
  scenes with other numbers and colours of objects;
- ``pull-in-order``: the ordered set <orange, green, yellow>, reproduced with VSL from a single
  demonstration and with VSL-SP through ``sometime-before`` constraints.

The trials themselves are :func:`vslsp.loop.experiments.run_trial`. The report shows, for one
trial, every observed pre/post pair with its grounding drawn (and the raw images beside, to
feed to ``vslsp ground``), the learned ``domain.pddl``, the first ``problem.pddl`` and plan,
and a figure of the executed hand trajectories.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from vslsp.outputs import atomic_file, write_text
from vslsp.tasks.base import Option, System, Task, TrialResult
from vslsp.tasks.registry import register

DEFAULT_PLANNER = "fast-downward"


class IcubExperiment(Task):
    """An iCub experiment: options ``faults``, ``planner`` and ``skills`` (the library folder)."""

    system = System.VSL_SP
    options = frozenset({Option.FAULTS, Option.PLANNER, Option.SKILLS, Option.PREDICATES})
    keep_first = True  # a trial takes tens of seconds: the first one's artefacts travel back instead of a re-run

    def check(self) -> None:
        """The skill library loads and has push and pull (a missing or corrupt one, or a missing
        skill, is reported before any work); the planner exists."""
        from vslsp.skills.library import SKILL_NAMES, SkillLibrary
        from vslsp.symbolic import check_planner

        check_planner(self.option(Option.PLANNER, DEFAULT_PLANNER))
        SkillLibrary.load(self.library_path).require(SKILL_NAMES, self.library_path)
        self.predicates()  # a predicates file that does not load is reported before any work

    @property
    def library_path(self) -> Path:
        from vslsp.skills.library import default_library_path

        skills = self.option(Option.SKILLS)
        return Path(skills) if skills else default_library_path()

    def predicates(self) -> tuple:
        """The user's predicates (``--predicates FILE.py``), loaded from the file; () without one."""
        from vslsp.grounding import load_predicates

        path = self.option(Option.PREDICATES)
        return tuple(load_predicates(path)) if path else ()

    def run_trial(self, seed: int, keep: bool = False, on_stage=None, gui: bool = False) -> TrialResult:
        from vslsp.loop.experiments import run_trial
        from vslsp.skills.library import SkillLibrary

        trial = run_trial(
            self.name,
            seed,
            SkillLibrary.load(self.library_path),
            faults=bool(self.option(Option.FAULTS, False)),
            planner=self.option(Option.PLANNER, DEFAULT_PLANNER),
            gui=gui,
            on_stage=on_stage,
            predicates=self.predicates(),
        )
        record = trial.to_dict()
        operations = [{"operation": i, **step.to_dict()} for i, step in enumerate(trial.steps, start=1)]
        details = {k: v for k, v in record.items() if k not in ("experiment", "seed", "success", "error", "time_s")}
        return TrialResult(
            self.name,
            seed,
            trial.success,
            trial.error,
            operations=operations,
            details=details,
            artefacts=trial if keep else None,
        )

    def summary(self, results: list[TrialResult]) -> dict:
        return {
            "faults": bool(self.option(Option.FAULTS, False)),
            "replans": sum(r.details.get("replans", 0) for r in results),
            "failed_steps": sum(r.details.get("failed_steps", 0) for r in results),
        }

    def shown_seed(self, results: list[TrialResult]) -> int:
        return results[0].seed  # kept by the run (keep_first)

    def markdown(self, data: Mapping[str, Any]) -> list[str]:
        return [
            f"{data['replans']} replans, {data['failed_steps']} failed steps"
            f"{', faults injected' if data['faults'] else ''}.",
            "",
        ]

    def figures(self, folder: Path, shown: TrialResult) -> dict[str, Any]:
        trial = shown.artefacts
        files = _write_artefacts(folder, trial)
        if trial.task is not None:
            files["rules"] = [str(rule) for rule in trial.task.rules]
        return files


@register
class SimpleVslTask(IcubExperiment):
    name = "simple-vsl-task"
    paper_section = "VSL-SP Results: simple VSL task"
    description = (
        "Three cubes, one demonstrated sequence, reproduced by VSL's own planner (match finding with "
        "adaptive frames, no PDDL) in a reshuffled scene."
    )


@register
class KeepAllNear(IcubExperiment):
    name = "keep-all-near"
    paper_section = "VSL-SP Results: keep all objects near"
    description = (
        "Three demonstrations teach the rule 'no block is far', which then solves scenes with other "
        "numbers and colours of objects (PDDL + Fast Downward)."
    )


@register
class PullInOrder(IcubExperiment):
    name = "pull-in-order"
    paper_section = "VSL-SP Results: pull in order"
    description = (
        "The ordered set <orange, green, yellow>, reproduced with VSL from a single demonstration and with "
        "VSL-SP through sometime-before constraints."
    )


def _write_artefacts(folder: Path, trial) -> dict:
    from vslsp.grounding import draw_grounding
    from vslsp.vision.image import write_image

    files: dict = {"images": []}
    images = folder / "images"
    images.mkdir(exist_ok=True)
    for i, (title, pre, post, grounding) in enumerate(trial.observations, start=1):
        picture = draw_grounding(pre, post, grounding) if grounding is not None else np.hstack([pre, post])
        name = f"{i:02d}_{re.sub(r'[^a-z0-9]+', '_', title.lower()).strip('_')}.png"
        write_image(images / name, picture)
        stem = name[:-4]
        (raw := images / "raw").mkdir(exist_ok=True)
        write_image(raw / f"{stem}_pre.png", pre)  # the camera's own images, for `vslsp ground PRE POST`
        write_image(raw / f"{stem}_post.png", post)
        files["images"].append(
            {
                "title": title,
                "file": f"images/{name}",
                "pre": f"images/raw/{stem}_pre.png",
                "post": f"images/raw/{stem}_post.png",
                "grounding": grounding.to_dict() if grounding is not None else None,
            }
        )
    if trial.domain is not None:
        write_text(folder / "domain.pddl", trial.domain.to_pddl())
        files["domain"] = "domain.pddl"
    runs = [run for run in trial.executions if run.problems]
    if runs:
        write_text(folder / "problem.pddl", runs[0].problems[0].to_pddl())
        files["problem"] = "problem.pddl"
        plans = [plan for run in runs for plan in run.plans]
        write_text(folder / "plan.txt", plans[0].to_pddl())
        files["plan"] = "plan.txt"
        files["plans"] = [plan.to_dict() for plan in plans]
        files["executions"] = [run.to_dict() for run in runs]
    if trial.task is not None:
        files["task"] = trial.task.to_dict()
    trajectories = [s for s in trial.steps if s.trajectory is not None]
    if trajectories:
        _plot_trajectories(folder / "trajectories.png", trial)
        files["trajectories"] = "trajectories.png"
    return files


def _plot_trajectories(path: Path, trial) -> None:
    """The executed hand paths (top view) and heights: VSL-SP's plan steps solid, VSL's
    match-finding reproduction dashed, each in its cube's colour; a dot ends each path."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    from vslsp.sim import COLOURS

    planned = {id(step) for run in trial.executions for step in run.steps}
    fig, (top, side) = plt.subplots(1, 2, figsize=(12, 4.8))
    for k, step in enumerate(trial.steps, start=1):
        if step.trajectory is None:
            continue
        p = step.trajectory.position
        colour = COLOURS.get(step.obj.split("_")[0], (0.3, 0.3, 0.3))
        style = "-" if id(step) in planned else "--"
        top.plot(p[:, 1], p[:, 0], style, color=colour, lw=1.8)
        top.plot(p[-1, 1], p[-1, 0], "o", color=colour)
        top.annotate(str(k), (p[-1, 1], p[-1, 0]), textcoords="offset points", xytext=(4, 4), fontsize=8)
        side.plot(step.trajectory.t, p[:, 2] - p[:, 2].min(), style, color=colour, lw=1.5)
    handles = [
        Line2D([], [], color="k", ls="-", label="VSL-SP (planned step)"),
        Line2D([], [], color="k", ls="--", label="VSL (match finding)"),
        Line2D([], [], color="k", ls="", marker="o", label="end of a path (step number)"),
    ]
    handles += [
        Line2D([], [], color=COLOURS[c], lw=4, label=f"{c} cube")
        for c in dict.fromkeys(step.obj.split("_")[0] for step in trial.steps)
        if c in COLOURS
    ]
    top.set(xlabel="y (m, robot's left)", ylabel="x (m, away from the robot)", title="executed hand paths, top view")
    top.invert_xaxis()
    top.set_aspect("equal")
    top.legend(handles=handles, fontsize=7, loc="best")
    side.set(xlabel="t (s)", ylabel="hand height above its lowest point (m)", title="hand height")
    fig.tight_layout()
    with atomic_file(path) as stream:
        fig.savefig(stream, dpi=110, format="png")
    plt.close(fig)
