"""Report folders of experiment runs and of ``vslsp demo``.

A report folder holds ``report.json`` (machine-readable; the fields of ``vslsp experiment
--json`` per DESIGN.md, then the details), ``report.md`` (for people), the pre/post images of
every observed operation with the grounding drawn on them, the learned ``domain.pddl`` and
the first ``problem.pddl``, the plans (``plan.txt``, one ``(action arg)`` per line, the
format ``vslsp validate`` reads) and a figure of the executed hand trajectories.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np

from vslsp.experiments import Trial
from vslsp.vision.image import write_image
from vslsp.grounding.overlay import draw_grounding


def summary(experiment: str, trials: list[Trial], faults: bool = False) -> dict:
    """The JSON of ``vslsp experiment --json``."""
    successes = sum(t.success for t in trials)
    return {
        "experiment": experiment,
        "trials": len(trials),
        "successes": successes,
        "success_rate": successes / len(trials) if trials else 0.0,
        "faults": faults,
        "replans": sum(t.replans for t in trials),
        "failed_steps": sum(t.failed_steps for t in trials),
        "mean_time_s": round(float(np.mean([t.time_s for t in trials])), 2) if trials else 0.0,
        "failures": [{"seed": t.seed, "error": t.error} for t in trials if not t.success],
        "results": [t.to_dict() for t in trials],
    }


def write_report(folder: str | Path, experiment: str, trials: list[Trial], faults: bool = False) -> Path:
    """Write the report folder; the first trial's artefacts illustrate it. Returns the folder."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    data = summary(experiment, trials, faults)
    shown = trials[0]
    files = _write_artefacts(folder, shown)
    data["shown_trial"] = {"seed": shown.seed, **files}
    (folder / "report.json").write_text(json.dumps(data, indent=2) + "\n")
    (folder / "report.md").write_text(_markdown(data, shown, files))
    return folder


def _write_artefacts(folder: Path, trial: Trial) -> dict:
    files: dict = {"images": []}
    images = folder / "images"
    images.mkdir(exist_ok=True)
    for i, (title, pre, post, grounding) in enumerate(trial.observations, start=1):
        picture = draw_grounding(pre, post, grounding) if grounding is not None else np.hstack([pre, post])
        name = f"{i:02d}_{re.sub(r'[^a-z0-9]+', '_', title.lower()).strip('_')}.png"
        write_image(images / name, picture)
        files["images"].append({"title": title, "file": f"images/{name}",
                                "grounding": grounding.to_dict() if grounding is not None else None})
    if trial.domain is not None:
        (folder / "domain.pddl").write_text(trial.domain.to_pddl())
        files["domain"] = "domain.pddl"
    runs = [run for run in trial.executions if run.problems]
    if runs:
        (folder / "problem.pddl").write_text(runs[0].problems[0].to_pddl())
        files["problem"] = "problem.pddl"
        plans = [plan for run in runs for plan in run.plans]
        (folder / "plan.txt").write_text(plans[0].to_pddl())
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


def _plot_trajectories(path: Path, trial: Trial) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (top, side) = plt.subplots(1, 2, figsize=(11, 4.5))
    colours = plt.cm.viridis(np.linspace(0, 0.9, max(1, len(trial.steps))))
    for colour, step in zip(colours, trial.steps):
        if step.trajectory is None:
            continue
        p = step.trajectory.position
        label = f"{step.action} {step.obj}" + ("" if step.ok else " (failed)")
        top.plot(p[:, 1], p[:, 0], color=colour, label=label)
        top.plot(p[-1, 1], p[-1, 0], "o", color=colour)
        side.plot(step.trajectory.t, p[:, 2] - p[:, 2].min(), color=colour, label=label)
    top.set_xlabel("y (m, robot's left)")
    top.set_ylabel("x (m, away from the robot)")
    top.invert_xaxis()
    top.set_aspect("equal")
    top.set_title("executed hand paths, top view")
    top.legend(fontsize=7)
    side.set_xlabel("t (s)")
    side.set_ylabel("hand height above its lowest point (m)")
    side.set_title("hand height")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _markdown(data: dict, trial: Trial, files: dict) -> str:
    lines = [f"# {data['experiment']}", "",
             f"{data['successes']} of {data['trials']} trials succeeded "
             f"({100 * data['success_rate']:.1f} %), {data['replans']} replans, "
             f"{data['failed_steps']} failed steps{', faults injected' if data['faults'] else ''}; "
             f"{data['mean_time_s']} s per trial.", ""]
    if data["failures"]:
        lines += ["## Failures", ""] + [f"- seed {f['seed']}: {f['error']}" for f in data["failures"]] + [""]
    lines += [f"## Trial with seed {trial.seed}", "", "```json", json.dumps(trial.to_dict(), indent=2), "```", ""]
    if trial.task is not None:
        lines += ["Rules learned from the demonstrations:", ""]
        lines += [f"- {rule}" for rule in trial.task.rules] + [""]
    for name in ("domain", "problem", "plan"):
        if name in files:
            lines += [f"- {name}: [{files[name]}]({files[name]})"]
    if "trajectories" in files:
        lines += ["", "![executed hand trajectories](trajectories.png)"]
    lines += ["", "## Observations", ""]
    for image in files["images"]:
        lines += [f"### {image['title']}", "", f"![{image['title']}]({image['file']})", ""]
    return "\n".join(lines) + "\n"
