"""``vslsp ground PRE POST``: the moved object, the landmark, (far b) before and after, and with
``--predicates FILE.py`` every ground atom of the user's predicates (docs/grounding.md)."""

from __future__ import annotations

import contextlib
import json
from typing import Any

import click

from vslsp.cli.params import PIXELS


def grounding_options(function: Any) -> Any:
    """``--robot-side`` and ``--predicates FILE.py`` (as ``predicates_file``): how a pair of
    pictures is grounded, here and in ``vslsp learn-domain``."""
    function = click.option(
        "--predicates",
        "predicates_file",
        type=click.Path(dir_okay=False),
        default=None,
        help="A Python file of predicates (@predicate from vslsp.grounding) to ground for every object and "
        "ordered pair, before and after. The file runs as Python with your rights, like a pytest "
        "conftest.py, in a child process with time and memory limits (docs/grounding.md): use only files you trust.",
    )(function)
    return click.option(
        "--robot-side",
        type=click.Choice(["bottom", "top", "left", "right"]),
        default="bottom",
        show_default=True,
        help="The image edge the robot is beyond (bottom: the robot's own view).",
    )(function)


@click.command()
@click.argument("pre", type=click.Path(dir_okay=False))
@click.argument("post", type=click.Path(dir_okay=False))
@grounding_options
@click.option(
    "--min-move",
    type=PIXELS,
    default=None,
    help="Pixels: an object whose centre moved less was nudged, not operated, and is left out when more "
    "than one object moved; 0 counts every change [default: 1 % of the image diagonal, 8 at 640x480].",
)
@click.option(
    "--slip-detection",
    type=click.Choice(["on", "off"]),
    default="off",
    show_default=True,
    help="on: ground every object that moved and tell the operated one from those the tutor disturbed "
    "(as `vslsp experiment --slip-detection on`); off: exactly one object moved (after --min-move).",
)
@click.option("--json", "as_json", is_flag=True, help='Print one JSON object on stdout ({"error": ...} on failure).')
@click.option(
    "--overlay",
    type=click.Path(dir_okay=False),
    default=None,
    help="Write a PNG with the line, the object before and after, and the labels.",
)
def ground(
    pre: str,
    post: str,
    robot_side: str,
    predicates_file: str | None,
    min_move: float | None,
    slip_detection: str,
    as_json: bool,
    overlay: str | None,
) -> None:
    """Ground one demonstrated operation from its PRE- and POST-action images (PNG/JPEG; at least 32 and
    at most 8192 pixels a side, at most 40 megapixels)."""
    if slip_detection == "on" and predicates_file:
        raise click.UsageError(
            "--slip-detection on grounds (far b) of every moved object but not --predicates; leave out one of them"
        )
    if slip_detection == "on":
        _ground_moves(pre, post, robot_side, as_json, overlay)
        return
    _ground(pre, post, robot_side, predicates_file, min_move, as_json, overlay)  # errors: vslsp.cli.main (JSON too)


def _check_overlay(overlay: str, pre: str, post: str, predicates_file: str | None) -> None:
    from vslsp.outputs import refuse_input, refuse_link, refuse_special
    from vslsp.vision.image import check_image_output

    check_image_output(overlay)
    refuse_link(overlay, "--overlay")
    refuse_special(overlay, "--overlay")
    refuse_input(
        overlay,
        {"pre-action image": pre, "post-action image": post, "predicates file": predicates_file},
        "--overlay",
    )


def _ground(
    pre: str,
    post: str,
    robot_side: str,
    predicates_file: str | None,
    min_move: float | None,
    as_json: bool,
    overlay: str | None,
) -> None:
    from vslsp.grounding import draw_grounding, with_builtins
    from vslsp.grounding import ground as ground_pair
    from vslsp.grounding.contained import UserPredicates
    from vslsp.vision.change import default_min_move
    from vslsp.vision.image import read_image, write_image

    if overlay is not None:
        _check_overlay(overlay, pre, post, predicates_file)
    with contextlib.ExitStack() as stack:
        predicates = None
        if predicates_file:  # the user's code runs in a child process (vslsp.grounding.contained)
            predicates = with_builtins(stack.enter_context(UserPredicates.start(predicates_file)).predicates)
        pre_image, post_image = read_image(pre, "pre-action image"), read_image(post, "post-action image")
        tolerance = default_min_move(pre_image.shape) if min_move is None else min_move
        grounding = ground_pair(pre_image, post_image, robot_side=robot_side, predicates=predicates, min_move=tolerance)
    if overlay:
        write_image(overlay, draw_grounding(pre_image, post_image, grounding))
    if as_json:
        click.echo(json.dumps(grounding.to_dict()))
        return
    far = {True: "far", False: "not far"}
    click.echo(
        f"{grounding.name}: ({grounding.pre[0]:.0f}, {grounding.pre[1]:.0f}) -> "
        f"({grounding.post[0]:.0f}, {grounding.post[1]:.0f}) px, {far[grounding.far_pre]} -> "
        f"{far[grounding.far_post]}, action: {grounding.action or 'none'}"
    )
    atoms = grounding.to_dict().get("atoms")
    if atoms:
        click.echo(f"pre:  {' '.join(atoms['pre']) or '(none true)'}")
        click.echo(f"post: {' '.join(atoms['post']) or '(none true)'}")
    for name, moved in grounding.nudged:
        click.echo(f"left out: {name} moved {moved:g} px (less than --min-move {tolerance:g})")
    if overlay:
        click.echo(f"overlay: {overlay}")


def _ground_moves(pre: str, post: str, robot_side: str, as_json: bool, overlay: str | None) -> None:
    """``--slip-detection on``: every moved object grounded, the operated one told from the rest."""
    from vslsp.vision.image import read_image, write_image
    from vslsp.vsl.slips.colour import draw_moves, ground_moves

    if overlay is not None:
        _check_overlay(overlay, pre, post, None)
    pre_image, post_image = read_image(pre, "pre-action image"), read_image(post, "post-action image")
    moves = ground_moves(pre_image, post_image, robot_side=robot_side)
    if overlay:
        write_image(overlay, draw_moves(pre_image, post_image, moves))
    if as_json:
        click.echo(json.dumps({**moves.operated.to_dict(), "moves": moves.to_dict()}))
        return
    far = {True: "far", False: "not far"}
    for g in moves.moved:
        role = "operated" if g is moves.operated else "disturbed"
        click.echo(
            f"{g.name} ({role}): ({g.pre[0]:.0f}, {g.pre[1]:.0f}) -> ({g.post[0]:.0f}, {g.post[1]:.0f}) px, "
            f"{far[g.far_pre]} -> {far[g.far_post]}, action: {g.action or 'none'}"
        )
    if overlay:
        click.echo(f"overlay: {overlay}")
