"""The Panda's tabletop tasks through picture files, as a user with a camera over a table would
run VSL (docs/recordings.md): the tutor's demonstration photographed into a recording folder
(``NN-pre.png``, ``NN-mid.png``, ``NN-post.png``, ``calibration.json`` of the camera,
``names.json``, ``heights.json``), and the closed loop of the reproduction in a new scene of
:func:`~vslsp.experiments.seeds.reproduction_seed`: photograph, ask where to pick and place
(``vslsp vsl reproduce --step``), execute it with the Panda's pick-and-place skill, photograph
again, until the answer is done. The judge reads the ground truth, which the pictures never
carry: each operation's object relative to its anchor against the demonstration's.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from vslsp.errors import TaskFailed
from vslsp.experiments.seeds import reproduction_seed
from vslsp.experiments.tabletop import TabletopExperiment
from vslsp.experiments.tabletop_protocol import relation
from vslsp.geometry.poses import wrap
from vslsp.outputs import write_text
from vslsp.tasks.registry import get_task
from vslsp.vision.image import write_image
from vslsp.worlds.panda_table import PandaTable
from vslsp.worlds.panda_table import layouts as scenes

# The top-down view the Panda's tasks see the table in (vslsp.vsl.pick_place.TableView's defaults).
WORKSPACE = {"x": [0.22, 0.84], "y": [-0.42, 0.42], "px_per_m": 1500.0, "z": 0.02}

Ask = Callable[[Path], dict]  # a picture of the scene -> the answer of `vslsp vsl reproduce --step --json`


@dataclass(frozen=True)
class Goal:
    """The ground truth of a demonstration: per operation the item, its anchor (None: the
    table) and its pose relative to the anchor afterwards (x, y, yaw, bottom height difference)."""

    items: tuple[str, ...]
    anchors: tuple[str | None, ...]
    relative: tuple[tuple[float, float, float, float], ...]


def camera_calibration(world: PandaTable) -> dict:
    """The world's camera as ``calibration.json`` says it: OpenCV's camera matrix and the table
    frame's pose in the camera frame (rows of R: the camera's right, down and forward axes)."""
    camera = world.camera
    rotation = np.vstack(camera.axes())
    translation = -rotation @ np.asarray(camera.eye, float)
    return {
        "camera_matrix": camera.intrinsics().tolist(),
        "rotation": rotation.tolist(),
        "translation": translation.tolist(),
        "image_size": [camera.width, camera.height],
        "workspace": WORKSPACE,
    }


def write_recording(task_name: str, seed: int, folder: str | Path) -> Goal:
    """The tutor's demonstration of ``task_name`` in the world of ``seed`` photographed into
    ``folder`` (created) the documented way; the goal, on the ground truth."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    task = get_task(task_name)
    assert isinstance(task, TabletopExperiment), f"{task_name} is not a tabletop task"
    task = task.for_seed(seed)
    rng = np.random.default_rng(seed)
    items, anchors, relative, heights = [], [], [], []
    with PandaTable.from_layout(task.layout(rng, "demonstration"), seed) as world:
        write_text(folder / "calibration.json", json.dumps(camera_calibration(world), indent=2) + "\n")
        for k, (name, where, anchor) in enumerate(task.moves(rng), start=1):
            if k == 1:
                write_image(folder / f"{k:02d}-pre.png", world.observe())
            height = world.specs[name].size[2]
            pick_z = world.truth(name)[2] + height
            world.tutor_move(name, scenes.hold_placement(0))
            write_image(folder / f"{k:02d}-mid.png", world.observe())
            world.tutor_move(name, where(world))
            write_image(folder / f"{k:02d}-post.png", world.observe())
            heights.append({"height": height, "pick_z": pick_z, "place_z": world.truth(name)[2] + height})
            items.append(name)
            anchors.append(anchor)
            relative.append(relation(world, name, anchor))
    write_text(folder / "names.json", json.dumps(items) + "\n")
    write_text(folder / "heights.json", json.dumps(heights, indent=2) + "\n")
    return Goal(tuple(items), tuple(anchors), tuple(relative))


def closed_loop(task_name: str, seed: int, goal: Goal, folder: str | Path, ask: Ask, limit: int = 20) -> list[dict]:
    """The reproduction of ``task_name``'s demonstration in the new world of ``seed``'s
    :func:`~vslsp.experiments.seeds.reproduction_seed`, driven by the answers of ``ask``: the
    scene photographed into ``folder`` (``scene-NN.png``), each answered pick and place executed
    by the Panda, until the answer is done (at most ``limit`` questions). Returns, per answered
    operation in order, its errors against the goal just after it was executed (ground truth):
    position (m), angle (deg), level (m); and, under ``"final"``, whether the last operation of
    every item still holds at the end. Raises TaskFailed when a question got an error."""
    folder = Path(folder)
    task = get_task(task_name)
    assert isinstance(task, TabletopExperiment), f"{task_name} is not a tabletop task"
    task = task.for_seed(seed)
    rng = np.random.default_rng(reproduction_seed(seed))
    done: list[dict] = []
    with PandaTable.from_layout(task.layout(rng, "reproduction"), seed) as world:
        for n in range(1, limit + 1):
            scene = folder / f"scene-{n:02d}.png"
            write_image(scene, world.observe())
            answer = ask(scene)
            if "error" in answer:
                raise TaskFailed(f"{scene}: {answer['error']}")
            if answer.get("done"):
                break
            pick, place = answer["pick"], answer["place"]
            world.pick_and_place(
                (*pick["table_m"], pick["hand_angle_rad"]),
                (*place["table_m"], place["hand_angle_rad"]),
                answer["grasp_width_m"],
            )
            k = answer["operation"] - 1
            done.append({"operation": k + 1, **placement_errors(world, goal, k)})
        last = {item: k for k, item in enumerate(goal.items)}
        final = [placement_errors(world, goal, k) for k in sorted(last.values())]
    return done + [{"final": final}]


def placement_errors(world: PandaTable, goal: Goal, k: int) -> dict:
    """Operation ``k``'s object against its demonstrated relation now (ground truth)."""
    now = relation(world, goal.items[k], goal.anchors[k])
    wanted = goal.relative[k]
    return {
        "item": goal.items[k],
        "position_error_m": round(float(np.hypot(now[0] - wanted[0], now[1] - wanted[1])), 4),
        "angle_error_deg": round(float(np.degrees(abs(wrap(now[2] - wanted[2])))), 2),
        "level_error_m": round(abs(now[3] - wanted[3]), 4),
    }
