"""``vslsp scene``: build the tabletop world from a seed or a scene file and save the camera views."""

from __future__ import annotations

import json
from pathlib import Path

import click

from vslsp.cli.params import OUTPUT_FOLDER, check_display, count, int_range, seed_option

MAX_IMAGE_SIDE = 4096  # pixels, each side of a rendered view


@click.command()
@seed_option(help="Seed of the random scene (0 to 4294967295).")
@click.option(
    "--scene",
    "scene_file",
    type=click.Path(exists=True, dir_okay=False),
    default=None,
    help="A scene JSON file (cubes and landmark) instead of a random scene.",
)
@click.option("--cubes", type=int_range(1, 3), default=3, show_default=True, help="Number of cubes.")
@click.option(
    "--out",
    type=OUTPUT_FOLDER,
    default="out/scene",
    show_default=True,
    help="Folder for the views (created; must be writable).",
)
@click.option("--width", type=count(MAX_IMAGE_SIDE), default=640, show_default=True, help="Image width (px).")
@click.option("--height", type=count(MAX_IMAGE_SIDE), default=480, show_default=True, help="Image height (px).")
@click.option("--gui", is_flag=True, help="Open the pybullet window.")
def scene(seed: int, scene_file: str | None, cubes: int, out: Path, width: int, height: int, gui: bool) -> None:
    """Render the robot's head camera and the overhead camera (RGB PNG, depth .npy)."""
    check_display(gui)
    import numpy as np

    from vslsp.outputs import atomic_file, refuse_places, write_text
    from vslsp.sim import CAMERA_NAMES, LineWorld, SceneSpec
    from vslsp.vision.image import write_image

    names = [f"{n}{suffix}" for n in CAMERA_NAMES for suffix in (".png", "_depth.npy")]
    refuse_places(out, (*names, "scene.json", "ground_truth.json"))  # before the simulator starts
    spec = SceneSpec.load(scene_file) if scene_file else SceneSpec.random(seed, n_cubes=cubes)
    folder = out
    with LineWorld(spec, gui=gui) as world:
        for name in CAMERA_NAMES:
            observation = world.observe(name, width, height)
            write_image(folder / f"{name}.png", observation.rgb)
            with atomic_file(folder / f"{name}_depth.npy") as stream:
                np.save(stream, observation.depth)
        truth = {name: {"pose": world.cube_pose(name), "far": world.is_far(name)} for name in world.cubes}
    write_text(folder / "scene.json", json.dumps(spec.to_dict(), indent=2) + "\n")
    write_text(folder / "ground_truth.json", json.dumps(truth, indent=2) + "\n")
    click.echo(f"wrote {', '.join(f'{n}.png' for n in CAMERA_NAMES)} and scene.json to {folder}")
