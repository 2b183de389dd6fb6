"""``vslsp learn-domain FOLDER --out DIR``: VSL-SP's action models, goal and order learned from a
user's own image pairs of push/pull operations (docs/recordings.md, "A PDDL domain from
pictures"), written as the domain and problem ``vslsp plan`` takes."""

from __future__ import annotations

import contextlib
import json
from pathlib import Path

import click

from vslsp.cli.params import prepare_output_folder
from vslsp.errors import InputError

DOMAIN, PROBLEM, SUMMARY = "domain.pddl", "problem.pddl", "learned.json"


@click.command("learn-domain")
@click.argument("folder", type=click.Path(file_okay=False))
@click.option("--out", "out", required=True, type=click.Path(file_okay=False), help="The folder to write into.")
@click.option(
    "--predicates",
    "predicates_file",
    type=click.Path(dir_okay=False),
    default=None,
    help="A Python file of predicates (@predicate from vslsp.grounding) to ground besides far, as "
    "`vslsp ground --predicates` does: it runs as Python with your rights in a child process with "
    "limits (docs/grounding.md); use only files you trust.",
)
@click.option(
    "--robot-side",
    type=click.Choice(["bottom", "top", "left", "right"]),
    default="bottom",
    show_default=True,
    help="The image edge the robot is beyond (bottom: the robot's own view).",
)
@click.option("--json", "as_json", is_flag=True, help='Print one JSON object on stdout ({"error": ...} on failure).')
def learn_domain(folder: str, out: str, predicates_file: str | None, robot_side: str, as_json: bool) -> None:
    """Learn the PDDL domain and problem from the operations in FOLDER (01-pre.png, 01-post.png, ...
    and names.json, e.g. {"01": "pull red", "02": "push blue"}; optional explore/ of the robot's
    own executions): DIR/domain.pddl, DIR/problem.pddl (the demonstrated order as sometime-before
    constraints), DIR/learned.json and an overlay picture per pair."""
    from vslsp.grounding import draw_grounding, with_builtins
    from vslsp.grounding.contained import UserPredicates
    from vslsp.loop.picture_domain import learn_picture_domain, read_picture_folder
    from vslsp.outputs import refuse_places, write_text
    from vslsp.vision.image import write_image

    pictures = read_picture_folder(folder)  # every file checked before any work
    if Path(out).resolve() == Path(folder).resolve():
        raise InputError(f"--out {out} is the pictures' folder FOLDER; write the domain elsewhere")
    overlays = {
        id(p): _overlay(p.number, i > 0)
        for i, pairs in enumerate((pictures.demonstration, pictures.explorations))
        for p in pairs
    }
    prepare_output_folder(out)
    refuse_places(out, (DOMAIN, PROBLEM, SUMMARY, *overlays.values()))
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
