"""The report folder of every experiment run: ``report.json``, ``report.md`` and figures.

``report.json`` holds the summary (the keys of ``vslsp experiment --json``: ``experiment``,
``trials``, ``successes``, ``success_rate``, ``mean_time_s``, ``failures``, ``results``,
``report``, then the task's own fields) and every trial's record in seed order.
``report.md`` opens with a summary table a person can read (trials, successes, failures by
cause, time), then the task's own lines, the figures of one trial and a row per trial. The
figures are the task's (:meth:`~vslsp.tasks.base.Task.figures`) for the trial that
:meth:`~vslsp.tasks.base.Task.shown_seed` picks, re-run with its artefacts when the run did
not keep them (trials are deterministic, so the re-run is the same trial).
"""

from __future__ import annotations

import json
from collections import Counter
from pathlib import Path
from typing import Any

from vslsp.outputs import write_text
from vslsp.tasks.base import Task
from vslsp.tasks.runner import Run
from vslsp.tasks.statistics import pose_error, total_stages, wilson_interval
from vslsp.tasks.trial import run_one

#: A report says that its success rate says little when the rate's 95 % interval is wider than this.
WIDE_INTERVAL = 0.20


def summary(task: Task, run: Run, folder: Path | None = None) -> dict:
    """The JSON summary of a run (the ``--json`` output and the head of ``report.json``)."""
    results = run.results
    successes = sum(r.success for r in results)
    data: dict[str, Any] = {
        "experiment": task.name,
        "system": task.system.value,
        "paper_section": task.paper_section,
        "trials": len(results),
        "seed": run.seeds[0],
        "successes": successes,
        "success_rate": successes / len(results) if results else 0.0,
        "mean_time_s": round(sum(r.time_s for r in results) / len(results), 2) if results else 0.0,
        "failures": [{"seed": r.seed, "error": r.error or "goal not reached"} for r in results if not r.success],
        "failure_causes": dict(Counter(r.cause for r in results if not r.success).most_common()),
    }
    data["success_ci95"] = wilson_interval(successes, len(results))
    errors = pose_error([e for r in results for e in task.pose_errors(r)])
    if errors is not None:
        data["pose_error"] = errors
    stages = total_stages([r.stages_s for r in results])
    if stages is not None:
        data["stages_s"] = stages
    if run.partial or run.interrupted:
        data["partial"] = True
        data["trials_requested"] = len(run.seeds)
        data["interrupted"] = run.interrupted
    data.update(task.summary(results))
    from vslsp.provenance import provenance

    data["provenance"] = {**provenance(), "seeds": [run.seeds[0], run.seeds[-1]] if run.seeds else []}
    data["results"] = [r.to_dict() for r in results]
    data["report"] = str(folder) if folder is not None else None
    return data


def write_report(folder: str | Path, task: Task, run: Run, *, figures: bool = True) -> dict:
    """Write the report folder of ``run``; returns the summary written to ``report.json``.

    The report of the finished trials is written first (``report.json``, ``report.md``, each
    file replaced whole, :mod:`vslsp.outputs`), then the figures, which may re-run a trial, then
    the report again with them: an interrupt or a full disk during the figures leaves the
    trials' report in place. ``figures=False`` (or an interrupted run) skips the figures.
    """
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    data = summary(task, run, folder)
    _write(folder, task, data)
    if figures and run.results and not run.partial and not run.interrupted:
        seed = task.shown_seed(run.results)
        shown = next((r for r in run.results if r.seed == seed and r.artefacts is not None), None)
        if shown is None:
            shown = run_one(task, seed, keep=True)
        files = task.figures(folder, shown) if shown.artefacts is not None else {}
        data["shown_trial"] = {"seed": shown.seed, "success": shown.success, **files}
        if shown.video is not None and (folder / shown.video).exists():
            from vslsp.sim.video import preview

            data["shown_trial"]["video"] = shown.video
            data["shown_trial"]["video_preview"] = str(Path(shown.video).with_suffix(".gif"))
            preview(folder / shown.video, folder / data["shown_trial"]["video_preview"])
        _write(folder, task, data)
    return data


def _write(folder: Path, task: Task, data: dict) -> None:
    write_text(folder / "report.json", json.dumps(data, indent=2) + "\n")
    write_text(folder / "report.md", markdown(task, data))


def markdown(task: Task, data: dict) -> str:
    """``report.md``: the summary table first, then the task's lines, the figures, the trials."""
    title = f"# {data['experiment']} ({data['system']}, paper: {data['paper_section']})"
    causes = ", ".join(f"{cause}: {n}" for cause, n in data["failure_causes"].items()) or "none"
    lines = [title, ""]
    if task.description:
        lines += [task.description, ""]
    if data.get("partial"):
        lines += [
            f"**Partial run**: interrupted ({data['interrupted']}) after {data['trials']} of "
            f"{data['trials_requested']} trials; this report holds the finished trials, without figures.",
            "",
        ]
    lo, hi = data["success_ci95"]
    lines += [
        "| trials | succeeded | success rate (95 % CI, Wilson) | failures by cause | mean time per trial |",
        "|---|---|---|---|---|",
        f"| {data['trials']} (seeds {data['seed']}-{data['seed'] + max(data['trials'] - 1, 0)}) | "
        f"{data['successes']} | {100 * data['success_rate']:.1f} % ({100 * lo:.1f}-{100 * hi:.1f} %) | {causes} | "
        f"{data['mean_time_s']} s |",
        "",
    ]
    if hi - lo > WIDE_INTERVAL:
        lines += [
            f"**Few trials**: with {data['trials']} trial{'s' * (data['trials'] != 1)} the rate says little, its 95 % "
            f"interval spans {100 * lo:.0f}-{100 * hi:.0f} % (wider than {100 * WIDE_INTERVAL:.0f} points); run more "
            "(`--trials`) before comparing methods.",
            "",
        ]
    made = data.get("provenance")
    if made:
        commit = f", commit {made['commit'][:12]}{' with changes' if made['changed'] else ''}" if made["commit"] else ""
        lines += [
            f"Made by vslsp {made['vslsp']}{commit}, Python {made['python']}, {made['platform']}: `{made['command']}`",
            "",
        ]
    lines += _statistics(data)
    rows = task.paper_figures(data)
    if rows:
        lines += ["| measure | ours | paper |", "|---|---|---|"]
        lines += [f"| {measure} | {ours} | {paper} |" for measure, ours, paper in rows] + [""]
    lines += task.markdown(data)
    if data["failures"]:
        lines += ["## Failures", ""] + [f"- seed {f['seed']}: {f['error']}" for f in data["failures"][:30]]
        if len(data["failures"]) > 30:
            lines.append(f"- ... and {len(data['failures']) - 30} more (report.json)")
        lines.append("")
    shown = data.get("shown_trial")
    if shown:
        lines += [f"## Trial {shown['seed']} ({'succeeded' if shown['success'] else 'FAILED'})", ""]
        if shown.get("video"):
            lines += [
                f"[![the trial, filmed (preview)]({shown['video_preview']})]({shown['video']})",
                "",
                f"The whole trial as a video: [{shown['video']}]({shown['video']}) (H.264 MP4; the preview above "
                "plays it faster and smaller).",
                "",
            ]
        for key, value in shown.items():
            if isinstance(value, str) and value.endswith(".png"):
                lines += [f"### {key.replace('_', ' ')}", "", f"![{key}]({value})", ""]
            elif isinstance(value, str) and value.endswith((".pddl", ".txt")):
                lines += [f"- {key}: [{value}]({value})"]
            elif key == "rules" and value:
                lines += ["Rules learned from the demonstrations:", ""] + [f"- {rule}" for rule in value] + [""]
            elif key == "images":
                for image in value:
                    lines += [f"### {image['title']}", ""]
                    if image.get("caption"):
                        lines += [str(image["caption"]).replace(" / ", "  \n"), ""]
                    lines += [f"![{image['title']}]({image['file']})", ""]
                    if "pre" in image:
                        lines += [f"Raw images: [pre]({image['pre']}), [post]({image['post']})", ""]
        lines.append("")
    lines += ["## Trials", "", "| seed | result | time (s) | notes |", "|---|---|---|---|"]
    for record in data["results"]:
        video = f" [video]({record['video']})" if record.get("video") else ""
        lines.append(
            f"| {record['seed']} | {'ok' if record['success'] else 'FAILED'} | {record['time_s']} | "
            f"{_note(record)}{video} |"
        )
    return "\n".join(lines) + "\n"


def _statistics(data: dict) -> list[str]:
    """The time by stage and the pose errors, in words."""
    lines = []
    stages = data.get("stages_s")
    if stages:
        total = sum(stages.values()) or 1.0
        parts = ", ".join(f"{name} {seconds:.1f} s ({100 * seconds / total:.0f} %)" for name, seconds in stages.items())
        lines += [f"Time by stage, all trials together: {parts}.", ""]
    errors = data.get("pose_error")
    if errors:
        mm, deg = errors["mm"], errors["deg"]
        lines += [
            f"Final pose error over {errors['operations']} operations: {mm['mean']} ± {mm['sd']} mm "
            f"(median {mm['median']}, 95th percentile {mm['p95']}), {deg['mean']} ± {deg['sd']} deg "
            f"(median {deg['median']}, 95th percentile {deg['p95']}).",
            "",
        ]
    return lines


def _note(record: dict) -> str:
    if record.get("error"):
        return str(record["error"]).replace("|", "/")[:200]
    operations = record.get("operations") or []
    diagnoses = Counter(
        # A diagnosis of None is an operation that went as planned (VSL-3D's records say so).
        str(op.get("diagnosis") or ("ok" if op.get("success", True) else "failed"))
        for op in operations
        if isinstance(op, dict)
    )
    return ", ".join(f"{k}: {v}" for k, v in diagnoses.items()) if diagnoses else ""
