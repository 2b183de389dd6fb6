"""``vslsp ground PRE POST``: the moved object, the landmark and (far b) before and after."""

from __future__ import annotations

import json

import click


@click.command()
@click.argument("pre", type=click.Path(dir_okay=False))
@click.argument("post", type=click.Path(dir_okay=False))
@click.option("--robot-side", type=click.Choice(["bottom", "top", "left", "right"]), default="bottom",
              show_default=True, help="The image edge the robot is beyond (bottom: the robot's own view).")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object on stdout.")
@click.option("--overlay", type=click.Path(dir_okay=False), default=None,
              help="Write a PNG with the line, the object before and after, and the labels.")
def ground(pre: str, post: str, robot_side: str, as_json: bool, overlay: str | None) -> None:
    """Ground one demonstrated operation from its PRE- and POST-action images (PNG/JPEG)."""
    from vslsp.vision.image import read_image, write_image
    from vslsp.vsl.grounding import ground as ground_pair
    from vslsp.vsl.overlay import draw_grounding

    pre_image, post_image = read_image(pre), read_image(post)
    grounding = ground_pair(pre_image, post_image, robot_side=robot_side)
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
    if overlay:
        click.echo(f"overlay: {overlay}")
