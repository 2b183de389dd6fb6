"""The report of the iCub experiments (VSL-SP): captioned pictures of every observed step, what
was learned (the action models as the paper's Table 3, the goal and the order), the faults
explained, a row per trial, and the executed hand paths of VSL-SP and VSL side by side.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from vslsp.errors import VslspError
from vslsp.experiments.icub_faults import fault_of
from vslsp.grounding import draw_grounding
from vslsp.grounding.operation import Grounding, ground
from vslsp.outputs import atomic_file, output_subfolder, write_text
from vslsp.sim import COLOURS
from vslsp.tasks.drawing import caption, label
from vslsp.vision.change import default_min_move
from vslsp.vision.image import write_image
from vslsp.vsl.slips.colour import draw_moves

# The paper's Table 3: the preconditions and effects VSL extracts for push and pull.
TABLE_3 = {
    "push": ("(not (far ?b))", "(far ?b)"),
    "pull": ("(far ?b)", "(not (far ?b))"),
}


def step_caption(title: str, grounding, step, fault: dict | None) -> list[str]:
    """The words under a picture: what the step was, what was expected and seen, the fault."""
    lines = [title]
    if step is None and grounding is not None and grounding.action:
        seen = "far" if grounding.far_post else "near"
        lines[0] += f": {grounding.action} {grounding.name} (seen ending {seen})"
    if step is not None:
        verdict = "ok" if step.ok else "effect MISSING"
        lines.append(f"expected {step.expected}, observed {step.observed}: {verdict}")
    if fault is not None:
        lines.append(f"FAULT {fault['kind']} ({fault['what']}); recovery: {fault['recovery']}")
    return lines


def observed_grounding(pre: np.ndarray, post: np.ndarray) -> tuple[Grounding | None, str]:
    """The grounding of an executed step's pre/post observation for its picture and record, as
    ``vslsp ground PRE POST`` gives it on the raw images written beside it (the same
    ``--min-move`` default: a neighbour the robot's hand nudged by a few pixels is left out),
    or None and why not (nothing moved: a skipped step; the images are still shown)."""
    try:
        return ground(pre, post, min_move=default_min_move(pre.shape)), ""
    except VslspError as error:
        return None, str(error).split(";")[0].split(" (")[0]  # e.g. "nothing moved between ... image"


def write_artefacts(folder: Path, trial, fault_log: list[dict]) -> dict:
    """Every observed pre/post pair drawn and captioned (with the camera's raw images), the
    learned PDDL, the first problem and plan, the executions, and the trajectory figure."""
    files: dict = {"images": []}
    images = output_subfolder(folder, "images")
    number = {id(step): k for k, step in enumerate(trial.steps, start=1)}
    faults = {entry["step"]: entry for entry in fault_log}
    for i, (title, pre, post, grounding, step) in enumerate(trial.observations, start=1):
        why = "no object changed side"
        if grounding is None and step is not None:
            grounding, why = observed_grounding(pre, post)
        # With the slip detection: every cube that moved, the operated one and the disturbed.
        moves = trial.watcher.pictures.get(i - 1) if getattr(trial, "watcher", None) is not None else None
        if moves is not None:
            picture = draw_moves(pre, post, moves)
        elif grounding is not None:
            picture = draw_grounding(pre, post, grounding)
        else:  # nothing moved, so nothing to ground: the two images, named
            picture = np.hstack([label(pre, "pre"), label(post, f"post: {why}")])
        fault = faults.get(number.get(id(step), -1)) if step is not None else None
        lines = step_caption(title, grounding, step, fault)
        if moves is not None:
            lines.append(moves_caption(moves))
        name = f"{i:02d}_{re.sub(r'[^a-z0-9]+', '_', title.lower()).strip('_')}.png"
        write_image(images / name, caption(picture, lines))
        stem = name[:-4]
        raw = output_subfolder(images, "raw")
        write_image(raw / f"{stem}_pre.png", pre)  # the camera's own images, for `vslsp ground PRE POST`
        write_image(raw / f"{stem}_post.png", post)
        files["images"].append(
            {
                "title": title,
                "file": f"images/{name}",
                "pre": f"images/raw/{stem}_pre.png",
                "post": f"images/raw/{stem}_post.png",
                "grounding": grounding.to_dict() if grounding is not None else None,
                "caption": " / ".join(lines),
            }
        )
        if moves is not None:
            files["images"][-1].update({k: v for k, v in moves.to_dict().items() if k in MOVES_KEYS})
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
    if any(s.trajectory is not None for s in trial.steps):
        plot_trajectories(folder / "trajectories.png", trial)
        files["trajectories"] = "trajectories.png"
    return files


MOVES_KEYS = ("moved", "operated", "disturbed")


def moves_caption(moves) -> str:
    """An operation's moves in words: ``moved: orange, yellow; operated: orange; disturbed: yellow
    (across the line: (far yellow) false -> true, not part of the goal)``."""
    disturbed = [
        g.name
        + (
            f" (across the line: (far {g.name}) {str(g.far_pre).lower()} -> {str(g.far_post).lower()}, "
            "not part of the goal)"
            if g.far_pre != g.far_post
            else ""
        )
        for g in moves.disturbed
    ]
    return (
        f"moved: {', '.join(g.name for g in moves.moved)}; operated: {moves.operated.name}; "
        f"disturbed: {', '.join(disturbed) or 'none'}"
    )


OFF = "off (the paper's VSL: one moved object per operation)"


def slip_lines(data: Mapping[str, Any]) -> list[str]:
    """report.md's "Tutor slips": the run's figures and each trial's disturbances in words (only
    for a run with ``--tutor-slips`` or ``--slip-detection``)."""
    if "tutor_slips" not in data:
        return []
    lines = [
        "## Tutor slips",
        "",
        f"P = {data['tutor_slips']} per demonstrated operation, slip detection "
        f"{'on' if data['slip_detection'] else OFF}: "
        f"{data['operations_slipped']} operations slipped, {data['slips_detected']} of those slips detected "
        f"(the slipped cube among the disturbed), {data['operated_not_the_tutors']} operations whose operated cube "
        f"was not the tutor's, {data['slips_across_the_line']} slips across the line.",
        "",
    ]
    for r in data["results"]:
        for op in r.get("tutor_operations", []):
            if "slip" not in op and not op.get("disturbed") and "error" not in op:
                continue
            seen = (
                f"error: {op['error']}"
                if "error" in op
                else f"moved {', '.join(op['moved'])}; operated {op['operated']}; "
                f"disturbed {', '.join(op['disturbed']) or 'none'}"
            )
            slip = op.get("slip")
            truth = (
                f"; the slip (truth): {slip['object']} by ({slip['dx_mm']}, {slip['dy_mm']}) mm, {slip['dyaw_deg']} deg"
                if slip and slip.get("applied")
                else ""
            )
            where = f"trial {r['seed']}, {op['demonstration']} operation {op['operation']} ({op['tutor']})"
            lines.append(f"- {where}: {seen}{truth}")
        lines += [f"  - {note}" for note in r.get("disturbances", [])]
    return lines + [""]


def matches_table_3(learned: Mapping[str, Any]) -> bool:
    """Whether the learned push and pull models are the paper's Table 3 (up to the variable's name)."""
    models = {m["action"]: m for m in learned.get("action_models", [])}
    for action, (pre, eff) in TABLE_3.items():
        model = models.get(action)
        if model is None:
            return False
        variable = model["parameters"].split()[0] if model["parameters"] else "?b"
        if (_rename(model["precondition"], variable), [_rename(e, variable) for e in model["effects"]]) != (pre, [eff]):
            return False
    return True


def _rename(pddl: str, variable: str) -> str:
    return re.sub(re.escape(variable) + r"\b", "?b", pddl)


def learned_lines(results: list[dict]) -> list[str]:
    """report.md's "What was learned": the action models as the paper's Table 3 (with the
    paper's beside) and their PDDL, then the goal, the order and the rules; each distinct
    content once, with the trials that learned it."""
    lines: list[str] = []
    learned = [(r["seed"], r["learned"]) for r in results if r.get("learned")]
    if not learned:
        return lines
    lines += ["## What was learned", ""]
    for seeds, model in _grouped(learned, ("action_models", "domain_pddl")):
        if not model.get("action_models"):
            continue
        lines += [
            f"### Action models, trials {seeds} (learned from the robot's own executions; the paper's Table 3 beside)",
            "",
            "| action | preconditions | effects | paper: preconditions | paper: effects |",
            "|---|---|---|---|---|",
        ]
        for action in model["action_models"]:
            paper = TABLE_3.get(action["action"], ("-", "-"))
            lines.append(
                f"| {action['action']} {action['parameters']} | `{action['precondition']}` | "
                f"`{' '.join(action['effects'])}` | `{paper[0]}` | `{paper[1]}` |"
            )
        lines += ["", "```lisp", model["domain_pddl"].rstrip(), "```", ""]
    for seeds, task in _grouped(learned, ("goal", "constraints", "rules")):
        if "goal" not in task:
            continue
        lines += [f"### Goal and order, trials {seeds}", "", f"Goal: `{task['goal']}`", ""]
        order = task.get("constraints") or []
        if order:
            lines += ["Ordering constraints (PDDL 3):", ""] + [f"- `{c}`" for c in order] + [""]
        else:
            lines += ["No ordering constraints (the order is free).", ""]
        if task.get("rules"):
            lines += ["Rules generalised from the demonstrations:", ""] + [f"- {r}" for r in task["rules"]] + [""]
    return lines


def _grouped(learned: list[tuple[int, dict]], keys: tuple[str, ...]) -> list[tuple[str, dict]]:
    """The distinct values of ``keys`` in the trials' learned records, each with its seeds."""
    groups: dict[str, tuple[list[int], dict]] = {}
    for seed, record in learned:
        part = {k: record[k] for k in keys if k in record}
        groups.setdefault(repr(sorted(part.items())), ([], part))[0].append(seed)
    return [(", ".join(map(str, seeds)), part) for seeds, part in groups.values()]


def trial_rows(results: list[dict]) -> list[str]:
    """One row per trial: steps, faults, replans, plan length, planning time, each system's outcome."""
    lines = [
        "| seed | steps | faults (step: kind) | replans | plan length | planning (s) | VSL-SP | VSL | result |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in results:
        faults = ", ".join(f"{e['step']}: {e['kind']}" for e in r.get("fault_log", [])) or "-"
        sp, vsl = system_outcomes(r)
        lines.append(
            f"| {r['seed']} | {len(r.get('operations') or [])} | {faults} | {r.get('replans', 0)} | "
            f"{r.get('plan_length', '-')} | {r.get('planning_s', '-')} | {sp} | {vsl} | "
            f"{'ok' if r['success'] else 'FAILED'} |"
        )
    return lines + [""]


def system_outcomes(record: dict) -> tuple[str, str]:
    """The VSL-SP and VSL columns of a trial's row, from the documented fields of its record
    (docs/tasks.md): ``vsl_sp_success`` (and ``vsl_sp_order``), else the trial's success when it
    planned (``plan_length`` or ``planning_status``); ``vsl_success`` (and ``vsl_order``), else the
    trial's success when it reproduced with VSL (``acted``: the objects it acted on); "-" otherwise."""
    sp_ok = record.get("vsl_sp_success")
    if sp_ok is None and ("plan_length" in record or "planning_status" in record):
        sp_ok = record["success"]
    vsl_ok, order = record.get("vsl_success"), record.get("vsl_order")
    if vsl_ok is None and "acted" in record:
        vsl_ok, order = record["success"], record["acted"]
    return _outcome(sp_ok, record.get("vsl_sp_order")), _outcome(vsl_ok, order)


def _outcome(ok: bool | None, order: list | None) -> str:
    if ok is None:
        return "-"
    return ("ok" if ok else "FAILED") + (f" ({', '.join(order)})" if order else "")


def fault_lines(results: list[dict]) -> list[str]:
    """Each injected fault in words: where, what, what was expected and seen, how it was recovered."""
    entries = [(r["seed"], e) for r in results for e in r.get("fault_log", [])]
    if not entries:
        return []
    lines = ["## Faults", "", "| seed | step | fault | expected | observed | recovery |", "|---|---|---|---|---|---|"]
    for seed, e in entries:
        lines.append(
            f"| {seed} | {e['step']} | {e['kind']}: {e['what']} | `{e['expected']}` | `{e['observed']}` | "
            f"{e['recovery']} |"
        )
    return lines + [""]


def plot_trajectories(path: Path, trial) -> None:
    """The executed hand paths, top view, one panel per system (VSL-SP's plan steps, VSL's
    match-finding steps), each path in its cube's colour with its step number at its end
    (labels pushed apart so that none overlaps another), and the hand's height in time."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    planned = {id(step) for run in trial.executions for step in run.steps}
    numbered = [(k, s) for k, s in enumerate(trial.steps, start=1) if s.trajectory is not None]
    systems = [
        (name, [(k, s) for k, s in numbered if (id(s) in planned) == is_planned])
        for name, is_planned in (("VSL-SP (planned steps)", True), ("VSL (match finding)", False))
    ]
    systems = [(name, steps) for name, steps in systems if steps]
    fig, axes = plt.subplots(1, len(systems) + 1, figsize=(5.2 * (len(systems) + 1), 5.0))
    tops, side = axes[:-1], axes[-1]
    all_xy = np.vstack([s.trajectory.position[:, :2] for _, s in numbered])
    pad = 0.03
    for top, (name, steps) in zip(tops, systems):
        for _, step in steps:
            p = step.trajectory.position
            colour = COLOURS.get(step.obj.split("_")[0], (0.3, 0.3, 0.3))
            top.plot(p[:, 1], p[:, 0], "-", color=colour, lw=1.8)
            top.plot(p[-1, 1], p[-1, 0], "o", color=colour, ms=6, mec="k", mew=0.6)
        top.set(
            xlim=(all_xy[:, 1].max() + pad, all_xy[:, 1].min() - pad),
            ylim=(all_xy[:, 0].min() - pad, all_xy[:, 0].max() + pad),
            xlabel="y (m, robot's left)",
            ylabel="x (m, away from the robot)",
            title=f"{name}: hand paths, top view",
            aspect="equal",
        )
    for top, (name, _) in zip(tops, systems):
        idle = [
            f"{k} ({f'fault {fault_of(s)}' if fault_of(s) else 'not executed'})"
            for k, s in enumerate(trial.steps, start=1)
            if s.trajectory is None and (id(s) in planned) == name.startswith("VSL-SP")
        ]
        if idle:
            top.text(0.02, 0.02, f"no hand path: step {', '.join(idle)}", transform=top.transAxes, fontsize=8)
    fig.tight_layout()
    fig.canvas.draw()  # the axes' final transforms, to place the step labels in pixels
    for top, (_, steps) in zip(tops, systems):
        _label_ends(top, [(k, s.trajectory.position[-1]) for k, s in steps])
    clock = 0.0
    for k, step in numbered:
        t, p = step.trajectory.t + clock, step.trajectory.position
        colour = COLOURS.get(step.obj.split("_")[0], (0.3, 0.3, 0.3))
        side.plot(t, p[:, 2] - p[:, 2].min(), "-" if id(step) in planned else "--", color=colour, lw=1.5)
        side.annotate(str(k), (t[len(t) // 2], float(np.ptp(p[:, 2]))), ha="center", va="bottom", fontsize=8)
        clock = t[-1] + 0.5
    handles = [
        Line2D([], [], color="k", ls="-", label="VSL-SP step"),
        Line2D([], [], color="k", ls="--", label="VSL step"),
    ] + [
        Line2D([], [], color=COLOURS[c], lw=4, label=f"{c} cube")
        for c in dict.fromkeys(step.obj.split("_")[0] for _, step in numbered)
        if c in COLOURS
    ]
    side.set(xlabel="t (s, steps one after another)", ylabel="hand height above its lowest point (m)")
    side.set_title("hand height per step (number = step)")
    side.legend(handles=handles, fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=3)
    with atomic_file(path) as stream:
        fig.savefig(stream, dpi=110, format="png", bbox_inches="tight")
    plt.close(fig)


def _label_ends(ax, ends: list[tuple[int, np.ndarray]]) -> None:
    """Step numbers beside the paths' ends (x, y, z), each moved up until its box is clear of
    the boxes already placed (measured as drawn), with a thin leader line back to its end."""
    renderer = ax.figure.canvas.get_renderer()
    placed: list = []
    for k, end in sorted(ends, key=lambda item: (item[1][0], item[1][1])):
        rise = 6.0
        while True:
            note = ax.annotate(
                f"step {k}",
                (end[1], end[0]),
                xytext=(6.0, rise),
                textcoords="offset points",
                fontsize=8,
                bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": "0.6", "lw": 0.5},
                arrowprops={"arrowstyle": "-", "lw": 0.5, "color": "0.4"},
            )
            note.update_bbox_position_size(renderer)
            box = note.get_bbox_patch().get_window_extent(renderer)
            if not any(box.overlaps(other) for other in placed) or rise > 400:
                break
            note.remove()
            rise += 4.0
        placed.append(box)
