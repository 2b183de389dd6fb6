"""``vslsp vsl learn FOLDER --out DEMO`` and ``vslsp vsl reproduce DEMO SCENE``: VSL on a
user's own pictures (docs/recordings.md): a demonstration learned from a folder of numbered
pictures, and the next operation's pick and place in a picture of a new scene, one at a time
with ``--step SESSION`` (the user's robot acts, photographs, and asks again)."""

from __future__ import annotations

import json
from pathlib import Path

import click
import numpy as np

from vslsp.cli.params import prepare_output_file
from vslsp.cli.recordings import JSON_HELP, learn_options, max_pixels_option, prepare_learned, reply, reproduce_options
from vslsp.errors import InputError


@click.group()
def vsl() -> None:
    """VSL (Algorithm 1) on your own pictures: learn a demonstration, reproduce it in a new scene."""


@vsl.command()
@learn_options("DEMO")
@max_pixels_option
def learn(folder: str, out: str, as_json: bool, max_pixels: int) -> None:
    """Learn the demonstration in FOLDER (01-pre.png, 01-mid.png, 01-post.png, ...; optional
    calibration.json, names.json, heights.json: docs/recordings.md) into the folder --out: the
    moved object of every operation, its pick and place, its features, the recorded
    observations and an annotated picture of each operation."""
    from vslsp.vsl.learned import FEATURES, RECORD, save_learned
    from vslsp.vsl.recordings import learn as learn_recording
    from vslsp.vsl.recordings import read_recording

    recording = read_recording(folder, max_pixels)  # every file checked before any work
    names = [RECORD, FEATURES] + [
        f"{i:02d}-{which}.png"
        for i in range(1, len(recording.observations) + 1)
        for which in ("pre-pick", "pre-place", "post-place", "annotated")
    ]
    prepare_learned(folder, out, tuple(names))
    demo = learn_recording(recording)
    path = save_learned(demo, recording, out)
    pictures = _annotate(demo, recording.names, Path(out))
    operations: list[dict] = [
        {
            "operation": i,
            "name": recording.names[i - 1],
            "pick_point_px": [round(c, 1) for c in op.pick_point],
            "place_point_px": [round(c, 1) for c in op.place_point],
            "turn_rad": round(op.turn, 4),
            "features": len(op.features),
            "annotated": picture,
        }
        for i, (op, picture) in enumerate(zip(demo.operations, pictures), start=1)
    ]
    if as_json:
        click.echo(
            json.dumps(
                {
                    "demonstration": str(path),
                    "calibrated": recording.calibration.calibrated,
                    "operations": operations,
                }
            )
        )
        return
    for op in operations:
        click.echo(
            f"operation {op['operation']} ({op['name']}): pick at {op['pick_point_px']} px, place at "
            f"{op['place_point_px']} px (seen from above), turned {np.degrees(op['turn_rad']):.1f} deg; "
            f"{op['features']} features"
        )
    click.echo(f"learned {len(operations)} operations into {path}")


def _annotate(demo, names: tuple[str, ...], folder: Path) -> list[str]:
    """Each operation's three observations side by side, the pick frame on the pre-pick one
    and the place frame on the pre-place one; the files' names."""
    from vslsp.tasks.drawing import PICK, PLACE, label, small, square
    from vslsp.vision.image import write_image

    files = []
    for i, op in enumerate(demo.operations, start=1):
        pre, pre_place, post = op.pre_pick.copy(), op.pre_place.copy(), op.post_place.copy()
        square(pre, op.pick_point, demo.pick_frame, PICK)
        square(pre_place, op.place_point, demo.place_frame, PLACE)
        square(post, op.place_point, demo.pick_frame, PICK)
        picture = np.hstack(
            [
                label(small(pre), f"{i}: pre-pick ({names[i - 1]})"),
                label(small(pre_place), f"{i}: pre-place (place frame)"),
                label(small(post), f"{i}: post-place"),
            ]
        )
        name = f"{i:02d}-annotated.png"
        write_image(folder / name, picture)
        files.append(name)
    return files


@vsl.command()
@reproduce_options("photographs")
@click.option("--json", "as_json", is_flag=True, help=JSON_HELP)
def reproduce(demo: str, scene: str, session_file: str | None, operation: int, as_json: bool) -> None:
    """The next operation's pick and place in SCENE (a picture of the new scene by the camera
    of the demonstration): pixels of SCENE and, with a calibration, table metres."""
    from vslsp.vision.image import read_image
    from vslsp.vsl.learned import load_learned, next_operation

    learned = load_learned(demo)

    def fits(width: int, height: int) -> None:  # from the header, before the picture is decoded
        if (width, height) != learned.size:
            raise InputError(
                f"{scene} is {width}x{height} px, the demonstration's pictures "
                f"{learned.size[0]}x{learned.size[1]}: photograph the scene with the demonstration's camera"
            )

    image = read_image(scene, fits=fits)
    count = len(learned)
    reply(demo, scene, session_file, operation, count, lambda k: next_operation(learned, k, image), as_json, _told)


def _told(answer: dict) -> list[str]:
    """The lines of a reproduction's answer."""
    lines = [f"operation {answer['operation']} of {answer['operations']} ({answer['name']}):"]
    for role in ("pick", "place"):
        where = answer[role]
        line = f"  {role} at ({where['pixel'][0]:.1f}, {where['pixel'][1]:.1f}) px"
        if "table_m" in where:
            line += (
                f", table ({where['table_m'][0]:.4f}, {where['table_m'][1]:.4f}) m, hand angle "
                f"{np.degrees(where['hand_angle_rad']):.1f} deg"
            )
        lines.append(line)
    lines.append(f"  turn the object {np.degrees(answer['turn_rad']):.1f} deg")
    return lines


@vsl.command()
@click.argument("images", nargs=-1, required=True, type=click.Path(dir_okay=False))
@click.option(
    "--checkerboard",
    "pattern",
    default=None,
    help="COLSxROWS: the inner corners of a checkerboard lying on the table (every IMAGE shows it; "
    "with two or more, the lens distortion is fitted too).",
)
@click.option("--square", type=float, default=None, help="With --checkerboard: a square's side in millimetres.")
@click.option(
    "--points",
    "points",
    is_flag=True,
    help="IMAGE then four or more pairs u,v:x,y (image pixels : table metres): a homography.",
)
@click.option("--out", "out", required=True, type=click.Path(dir_okay=False), help="The calibration.json to write.")
@click.option("--json", "as_json", is_flag=True, help=JSON_HELP)
def calibrate(
    images: tuple[str, ...], pattern: str | None, square: float | None, points: bool, out: str, as_json: bool
) -> None:
    """Write calibration.json (docs/recordings.md) from pictures of a checkerboard on the table
    (--checkerboard COLSxROWS --square MM IMAGE...) or from table points marked in one picture
    (--points IMAGE u,v:x,y u,v:x,y u,v:x,y u,v:x,y)."""
    from vslsp.outputs import write_text
    from vslsp.vision.image import read_image
    from vslsp.vsl.calibrate import checkerboard_calibration, parse_pattern, parse_points, points_calibration

    if (pattern is None) == (not points):
        raise InputError("give either --checkerboard COLSxROWS --square MM or --points (not both)")
    if points:
        image_file, *pairs = images
        pixels, table = parse_points(pairs)
        prepare_output_file(out)
        image = read_image(image_file)
        data = points_calibration(pixels, table, (image.shape[1], image.shape[0]), image_file)
    else:
        assert pattern is not None
        size = parse_pattern(pattern)
        if square is None or not square > 0:
            raise InputError("--square: give the side of a checkerboard square in millimetres (> 0)")
        prepare_output_file(out)
        pictures = [read_image(name) for name in images]
        data = checkerboard_calibration(pictures, images, size, square / 1000.0)
    write_text(out, json.dumps(data, indent=2) + "\n")
    if as_json:
        click.echo(json.dumps({"calibration": str(out), **data}))
        return
    error = f"reprojection {data['rms_px']:.3f} px" if "rms_px" in data else f"fit {1000 * data['rms_m']:.2f} mm"
    click.echo(f"wrote {out} ({'camera and table plane' if pattern else 'homography'}; {error})")
