"""``vslsp vsl3d``: VSL-3D's experiments (an alias of ``vslsp experiment`` for its tasks), and
VSL-3D on a user's own clouds (docs/recordings.md, "VSL-3D"): ``learn FOLDER --out DEMO`` and
``reproduce DEMO SCENE [--step SESSION]``, the next operation's object and its place."""

from __future__ import annotations

import json

import click

from vslsp.cli.experiment import experiment


@click.group()
def vsl3d() -> None:
    """VSL-3D: learn object reconfigurations from RGB-D point clouds: your own clouds, or the experiments."""


@vsl3d.command("table-cleaning", context_settings={"ignore_unknown_options": True})
@click.argument("args", nargs=-1, type=click.UNPROCESSED)
@click.pass_context
def table_cleaning(ctx: click.Context, args: tuple[str, ...]) -> None:
    """The table-cleaning experiment: the same as `vslsp experiment table-cleaning ARGS`."""
    experiment.main(["table-cleaning", *args], prog_name="vslsp experiment", standalone_mode=False)


_JSON_HELP = 'Print one JSON object on stdout ({"error": ...} on failure).'


@vsl3d.command()
@click.argument("folder", type=click.Path(file_okay=False))
@click.option("--out", "out", required=True, type=click.Path(file_okay=False), help="The folder to write DEMO into.")
@click.option("--json", "as_json", is_flag=True, help=_JSON_HELP)
def learn(folder: str, out: str, as_json: bool) -> None:
    """Learn the VSL-3D demonstration in FOLDER (01-pre.ply|pcd|npz or 01-pre-depth.png,
    01-post..., calibration.json, optional names.json: docs/recordings.md) into --out: per
    operation the moved object's pre-action observation and its motion (getObject)."""
    from pathlib import Path

    from vslsp.cli.params import prepare_output_folder
    from vslsp.errors import InputError
    from vslsp.outputs import refuse_places
    from vslsp.vsl3d.learned import OBSERVATIONS, RECORD, save_learned
    from vslsp.vsl3d.recordings import learn as learn_recording
    from vslsp.vsl3d.recordings import read_cloud_recording

    recording = read_cloud_recording(folder)  # every file checked before any work
    if Path(out).resolve() == Path(folder).resolve():
        raise InputError(f"--out {out} is the recording's folder FOLDER; write the demonstration elsewhere")
    prepare_output_folder(out)
    refuse_places(out, (RECORD, OBSERVATIONS))
    method, seed = "prerejective_ransac", 0
    moved = learn_recording(recording, method, seed)
    path = save_learned(moved, recording, out, method, seed)
    operations = [
        {
            "operation": i,
            "name": recording.names[i - 1],
            "pre_centroid_m": [round(float(c), 4) for c in obj.pre.centroid],
            "post_centroid_m": [round(float(c), 4) for c in obj.post.centroid],
            "rotation_deg": round(obj.to_dict()["rotation_deg"], 2),
            "fitness": round(obj.registration.fitness, 4),
            "points": len(obj.pre.points),
        }
        for i, obj in enumerate(moved, start=1)
    ]
    if as_json:
        click.echo(json.dumps({"demonstration": str(path), "operations": operations}))
        return
    for op in operations:
        click.echo(
            f"operation {op['operation']} ({op['name']}): from {op['pre_centroid_m']} m to {op['post_centroid_m']} m "
            f"(table frame), turned {op['rotation_deg']:.1f} deg; {op['points']} points, fitness {op['fitness']:.2f}"
        )
    click.echo(f"learned {len(operations)} operations into {path}")


@vsl3d.command()
@click.argument("demo", type=click.Path(file_okay=False))
@click.argument("scene", type=click.Path(dir_okay=False))
@click.option(
    "--step",
    "session_file",
    type=click.Path(dir_okay=False),
    default=None,
    help="A session file (JSON, created when missing): answer its next operation and move on, so that "
    'your robot acts, captures and asks again; {"done": true} when every operation is done.',
)
@click.option(
    "--operation",
    type=click.IntRange(min=1),
    default=1,
    show_default=True,
    help="Without --step: the operation to answer (1 = the first).",
)
@click.option(
    "--finger-open",
    type=click.FloatRange(min=0.005, max=0.5),
    default=0.04,
    show_default=True,
    help="How far (m) each finger of your gripper opens from its middle.",
)
@click.option("--json", "as_json", is_flag=True, help=_JSON_HELP)
def reproduce(
    demo: str, scene: str, session_file: str | None, operation: int, finger_open: float, as_json: bool
) -> None:
    """The next operation's object (its centroid and pose) and where to place it in SCENE (a
    .ply, .pcd or .npz cloud, or a -depth.png, by the demonstration's sensor): table frame and
    camera frame."""
    from vslsp.cli.params import prepare_output_file
    from vslsp.errors import InputError
    from vslsp.vsl.learned import Session
    from vslsp.vsl3d.learned import load_learned, next_operation
    from vslsp.vsl3d.recordings import read_world

    learned = load_learned(demo)
    world = read_world(scene, learned.calibration)
    session = None
    if session_file is not None:
        prepare_output_file(session_file, "--step")
        session = Session.open(session_file, demo, len(learned))
        k = session.next
    elif operation > len(learned):
        raise InputError(f"--operation {operation}: the demonstration has {len(learned)} operations")
    else:
        k = operation - 1
    if k >= len(learned):
        answer: dict = {"done": True, "operations": len(learned)}
    else:
        answer = next_operation(learned, k, world, finger_open)
        if session is not None and session_file is not None:
            session.next, session.given = k + 1, [*(session.given or []), {"scene": str(scene), **answer}]
            session.save(session_file)
    if as_json:
        click.echo(json.dumps(answer))
        return
    if answer["done"]:
        click.echo(f"done: all {answer['operations']} operations of the demonstration are done")
        return
    pick, place = answer["pick"], answer["place"]
    click.echo(
        "\n".join(
            [
                f"operation {answer['operation']} of {answer['operations']} ({answer['name']}):",
                f"  the object at {pick['centroid_m']} m (table frame), {pick['centroid_camera_m']} m (camera frame)",
                f"  grasp at {pick['grasp']['point_m']} m, hand at {pick['grasp']['hand_angle_rad']:.3f} rad",
                f"  place it at {place['centroid_m']} m (its centroid), fingertips at {place['grasp']['point_m']} m,"
                f" hand at {place['grasp']['hand_angle_rad']:.3f} rad; turned {answer['rotation_deg']:.1f} deg",
            ]
        )
    )
