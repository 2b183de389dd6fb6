"""``vslsp vsl3d``: VSL-3D's experiments (an alias of ``vslsp experiment`` for its tasks), and
VSL-3D on a user's own clouds (docs/recordings.md, "VSL-3D"): ``learn FOLDER --out DEMO`` and
``reproduce DEMO SCENE [--step SESSION]``, the next operation's object and its place."""

from __future__ import annotations

import json

import click

from vslsp.cli.experiment import experiment
from vslsp.cli.recordings import JSON_HELP, learn_options, max_size_option, prepare_learned, reply, reproduce_options


@click.group()
def vsl3d() -> None:
    """VSL-3D: learn object reconfigurations from RGB-D point clouds: your own clouds, or the experiments."""


@vsl3d.command("table-cleaning", context_settings={"ignore_unknown_options": True})
@click.argument("args", nargs=-1, type=click.UNPROCESSED)
@click.pass_context
def table_cleaning(ctx: click.Context, args: tuple[str, ...]) -> None:
    """The table-cleaning experiment: the same as `vslsp experiment table-cleaning ARGS`."""
    experiment.main(["table-cleaning", *args], prog_name="vslsp experiment", standalone_mode=False)


@vsl3d.command()
@learn_options("DEMO")
@max_size_option
def learn(folder: str, out: str, as_json: bool, max_bytes: int) -> None:
    """Learn the VSL-3D demonstration in FOLDER (01-pre.ply|pcd|npz or 01-pre-depth.png,
    01-post..., calibration.json, optional names.json: docs/recordings.md) into --out: per
    operation the moved object's pre-action observation and its motion (getObject)."""
    from vslsp.vsl3d.learned import OBSERVATIONS, RECORD, save_learned
    from vslsp.vsl3d.recordings import learn as learn_recording
    from vslsp.vsl3d.recordings import read_cloud_recording

    recording = read_cloud_recording(folder, max_bytes)  # every file checked before any work
    prepare_learned(folder, out, (RECORD, OBSERVATIONS))
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
@reproduce_options("captures")
@click.option(
    "--finger-open",
    type=click.FloatRange(min=0.005, max=0.5),
    default=0.04,
    show_default=True,
    help="How far (m) each finger of your gripper opens from its middle.",
)
@max_size_option
@click.option("--json", "as_json", is_flag=True, help=JSON_HELP)
def reproduce(
    demo: str, scene: str, session_file: str | None, operation: int, finger_open: float, max_bytes: int, as_json: bool
) -> None:
    """The next operation's object (its centroid and pose) and where to place it in SCENE (a
    .ply, .pcd or .npz cloud, or a -depth.png, by the demonstration's sensor): table frame and
    camera frame."""
    from vslsp.vsl3d.learned import load_learned, next_operation
    from vslsp.vsl3d.recordings import read_world

    learned = load_learned(demo)
    world = read_world(scene, learned.calibration, max_bytes)
    count = len(learned)

    def ask(k: int) -> dict:
        return next_operation(learned, k, world, finger_open)

    reply(demo, scene, session_file, operation, count, ask, as_json, _told)


def _told(answer: dict) -> list[str]:
    """The lines of a reproduction's answer."""
    pick, place = answer["pick"], answer["place"]
    return [
        f"operation {answer['operation']} of {answer['operations']} ({answer['name']}):",
        f"  the object at {pick['centroid_m']} m (table frame), {pick['centroid_camera_m']} m (camera frame)",
        f"  grasp at {pick['grasp']['point_m']} m, hand at {pick['grasp']['hand_angle_rad']:.3f} rad",
        f"  place it at {place['centroid_m']} m (its centroid), fingertips at {place['grasp']['point_m']} m,"
        f" hand at {place['grasp']['hand_angle_rad']:.3f} rad; turned {answer['rotation_deg']:.1f} deg",
    ]
