"""The table-cleaning experiment of VSL-3D through cloud files, as a user with a depth sensor
over a table would run VSL-3D (docs/recordings.md, "VSL-3D"): the tutor's demonstration
captured into a recording folder (``NN-pre`` / ``NN-post`` as PLY, PCD, ``.npz`` or depth PNG,
in the sensor's camera frame, and ``calibration.json``), and the closed loop of the
reproduction in the reshuffled scene: capture into a file, ask where to pick and place
(``vslsp vsl3d reproduce --step``), execute the answer with the Panda's pick-and-place, capture
again, until the answer is done. The judge reads the simulator's truth, which the files never
carry: each object's pose against the demonstrated one (:func:`table_cleaning.pose_error`).
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

import numpy as np

from vslsp.errors import TaskFailed
from vslsp.experiments.cloud_reproduction import WORKSPACE
from vslsp.experiments.table_cleaning import OPERATIONS, demonstration_layout, pose_error, reshuffle, tutor_operation
from vslsp.outputs import write_text
from vslsp.sim.cloud_scene import RGBDImage
from vslsp.vsl3d.cloud import DepthCamera
from vslsp.vsl3d.files import write_depth_png, write_pcd, write_ply
from vslsp.worlds.rgbd_table import RgbdTable

Ask = Callable[[Path], dict]  # a capture file of the scene -> the answer of `vslsp vsl3d reproduce --step --json`
FORMATS = ("ply", "ply-ascii", "pcd", "pcd-ascii", "npz", "depth")


def calibration(camera: DepthCamera) -> dict:
    """The sensor as ``calibration.json`` says it: K, the image size, the table frame's pose in
    the camera frame, and the table-cleaning workspace."""
    rotation = camera.pose[:3, :3].T
    return {
        "camera_matrix": camera.intrinsics.tolist(),
        "image_size": [camera.width, camera.height],
        "rotation": rotation.tolist(),
        "translation": (-rotation @ camera.pose[:3, 3]).tolist(),
        "workspace": WORKSPACE.to_dict(),
    }


def write_capture(image: RGBDImage, path_stem: Path, form: str) -> Path:
    """One capture written as a user's sensor would: a cloud of the camera frame (``ply``,
    ``pcd`` binary or ``-ascii``, ``npz``) or a millimetre depth PNG (``depth``); the file."""
    if form == "depth":
        path = path_stem.with_name(path_stem.name + "-depth.png")
        write_depth_png(path, image.depth)
        return path
    camera = DepthCamera.of(image.camera)
    points, _ = camera.back_project(image.depth)
    seen = (points - camera.pose[:3, 3]) @ camera.pose[:3, :3]  # the camera frame
    path = path_stem.with_name(f"{path_stem.name}.{form.split('-')[0]}")
    if form.startswith("ply"):
        write_ply(path, seen, binary=not form.endswith("ascii"))
    elif form.startswith("pcd"):
        write_pcd(path, seen, binary=not form.endswith("ascii"))
    else:
        np.savez_compressed(path, points=seen.astype(np.float32))
    return path


def write_cloud_recording(
    seed: int, folder: str | Path, forms: tuple[str, ...] = ("ply", "pcd")
) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """The tutor's table cleaning in the scene of ``seed`` captured into ``folder`` (created),
    operation k's files in ``forms[k % len(forms)]``; per object (truth) its pose (4, 4) before
    the tutor moved it and after."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(seed)
    layout = demonstration_layout(seed)
    goals = {}
    with RgbdTable(layout, robot=True) as scene:
        scene.park()
        image = scene.capture()
        write_text(folder / "calibration.json", json.dumps(calibration(DepthCamera.of(image.camera)), indent=2) + "\n")
        write_capture(image, folder / "01-pre", forms[0])
        for index, (name, _, _) in enumerate(OPERATIONS):
            start = scene.truth(name)
            tutor_operation(scene, layout, rng, index)
            write_capture(scene.capture(), folder / f"{index + 1:02d}-post", forms[index % len(forms)])
            goals[name] = (start, scene.truth(name))
    write_text(folder / "names.json", json.dumps([name for name, _, _ in OPERATIONS]) + "\n")
    return goals


def closed_loop(seed: int, truth: dict, folder: str | Path, ask: Ask, form: str = "ply", limit: int = 8) -> list[dict]:
    """The reproduction in the reshuffled scene of ``seed`` (``truth``: what
    :func:`write_cloud_recording` returned) driven by ``ask``'s answers: the
    scene captured into ``folder`` (``scene-NN``), each answer's grasp and place executed by the
    Panda, until the answer is done (at most ``limit`` questions). Per answered operation: the
    answer, what the fingers held and the object's pose error just after (truth); with it the
    answer's own errors, the pose M_j against the truth of where the object was."""
    folder = Path(folder)
    rng = np.random.default_rng(seed)
    layout = demonstration_layout(seed)
    for _ in OPERATIONS:  # the demonstration's draws (one turn an operation), then the reshuffle's
        rng.uniform(-1.0, 1.0)
    done: list[dict] = []
    with RgbdTable(reshuffle(layout, seed, rng), robot=True) as scene:
        movable = list(scene.bodies.values())
        for n in range(1, limit + 1):
            scene.park()
            scene.settle()
            answer = ask(write_capture(scene.capture(), folder / f"scene-{n:02d}", form))
            if "error" in answer:
                raise TaskFailed(f"scene {n}: {answer['error']}")
            if answer.get("done"):
                break
            name = OPERATIONS[answer["operation"] - 1][0]
            now = scene.truth(name)
            lower, upper = scene.bounds(name)
            centre = (lower + upper) / 2.0
            # M_j takes the recorded observation (where the object was in the demonstration) to the object now.
            found = pose_error(now @ np.linalg.inv(truth[name][0]), np.asarray(answer["pick"]["pose"]), centre)
            pick, place = answer["pick"]["grasp"], answer["place"]["grasp"]
            result = scene.grasp_and_place(
                np.asarray(pick["point_m"]), pick["hand_angle_rad"], np.asarray(place["point_m"]),
                place["hand_angle_rad"], movable,
            )  # fmt: skip
            scene.settle()
            lower, upper = scene.bounds(name)
            placed = pose_error(truth[name][1], scene.truth(name), (lower + upper) / 2.0)
            done.append(
                {
                    "operation": answer["operation"],
                    "name": name,
                    "held": result.held,
                    "found_error_mm": found[0],
                    "found_error_deg": found[1],
                    "final_error_mm": placed[0],
                    "final_error_deg": placed[1],
                }
            )
    return done
