"""``vslsp learn-domain FOLDER --out DIR``: VSL-SP's action models, goal and order learned from a
user's own image pairs of push/pull operations (docs/recordings.md, "A PDDL domain from
pictures"), written as the domain and problem ``vslsp plan`` takes."""

from __future__ import annotations

import contextlib
import json
from pathlib import Path

import click

from vslsp.cli.ground import grounding_options
from vslsp.cli.recordings import learn_options, max_pixels_option, prepare_learned

DOMAIN, PROBLEM, SUMMARY = "domain.pddl", "problem.pddl", "learned.json"


@click.command("learn-domain")
@learn_options("the domain, the problem and the overlays")
@grounding_options
@max_pixels_option
def learn_domain(
    folder: str, out: str, predicates_file: str | None, robot_side: str, as_json: bool, max_pixels: int
) -> None:
    """Learn the PDDL domain and problem from the operations in FOLDER (01-pre.png, 01-post.png, ...
    and names.json, e.g. {"01": "pull red", "02": "push blue"}; optional explore/ of the robot's
    own executions): DIR/domain.pddl, DIR/problem.pddl (the demonstrated order as sometime-before
    constraints), DIR/learned.json and an overlay picture per pair."""
    from vslsp.grounding import draw_grounding, with_builtins
    from vslsp.grounding.contained import UserPredicates
    from vslsp.loop.picture_domain import learn_picture_domain, read_picture_folder
    from vslsp.outputs import write_text
    from vslsp.vision.image import write_image

    pictures = read_picture_folder(folder, max_pixels)  # every file checked before any work
    overlays = {
        id(p): _overlay(p.number, i > 0)
        for i, pairs in enumerate((pictures.demonstration, pictures.explorations))
        for p in pairs
    }
    prepare_learned(folder, out, (DOMAIN, PROBLEM, SUMMARY, *overlays.values()), "the domain")
    with contextlib.ExitStack() as stack:
        predicates = None
        if predicates_file:  # the user's code runs in a child process (vslsp.grounding.contained)
            predicates = with_builtins(stack.enter_context(UserPredicates.start(predicates_file)).predicates)
        learned = learn_picture_domain(pictures, robot_side, predicates)
    folder_out = Path(out)
    write_text(folder_out / DOMAIN, learned.domain.to_pddl())
    write_text(folder_out / PROBLEM, learned.problem.to_pddl())
    for op in (*learned.demonstration, *learned.explorations):
        write_image(folder_out / overlays[id(op.pair)], draw_grounding(op.pair.pre, op.pair.post, op.grounding))
    summary = {
        "domain": str(folder_out / DOMAIN),
        "problem": str(folder_out / PROBLEM),
        "actions": [action.name for action in learned.domain.actions],
        "order": list(dict.fromkeys(op.step.obj for op in learned.demonstration)),
        "task": learned.task.to_dict(),
        "operations": [_operation(op, overlays[id(op.pair)]) for op in learned.demonstration],
        "explorations": [_operation(op, overlays[id(op.pair)]) for op in learned.explorations],
    }
    write_text(folder_out / SUMMARY, json.dumps(summary, indent=2) + "\n")
    if as_json:
        click.echo(json.dumps(summary))
        return
    for title, ops in (("exploration", summary["explorations"]), ("operation", summary["operations"])):
        for op in ops:
            far = op["far"]
            click.echo(
                f"{title} {op['operation']}: {op['action']} {op['object']}, "
                f"{_far(far['pre'])} -> {_far(far['post'])}; changed: "
                f"{', '.join(f'{p}={v}' for p, v in op['changed'].items())}"
            )
    click.echo(f"learned {', '.join(summary['actions'])}; order {' < '.join(summary['order'])}")
    click.echo(f"domain: {summary['domain']}\nproblem: {summary['problem']}")


def _overlay(number: str, explore: bool) -> str:
    return f"{'explore-' if explore else ''}{number}-overlay.png"


def _far(value: bool) -> str:
    return "far" if value else "not far"


def _operation(op, overlay: str) -> dict:
    """One pair in the summary: the moved object, far before and after, the atoms, what changed."""
    grounding = op.grounding.to_dict()
    data = {
        "operation": op.pair.number,
        "pre": op.pair.pre_file.name,
        "post": op.pair.post_file.name,
        "action": op.step.action,
        "object": op.step.obj,
        "far": grounding["far"],
        "changed": op.step.changed(),
        "overlay": overlay,
    }
    if "atoms" in grounding:
        data["atoms"] = grounding["atoms"]
    return data
