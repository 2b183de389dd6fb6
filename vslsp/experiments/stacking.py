"""The stacking experiment of VSL-3D, executed by the robot (paper, section "VSL-3D",
"Stacking Objects": objects at random places on the table and two boxes as dynamic landmarks;
the tutor stacks the objects on top of the boxes, and the robot reproduces the stacks with the
objects and the boxes at new random places and turns).

Demonstration: for each operation the tutor puts an object on top of its box; getObject finds
the object, its observations and its motion T_j, and the box it now stands on is cut from the
pre-action cloud (the segment under the post-action observation): the landmark observation B_j.
Reproduction: the boxes moved, so each is found in the new cloud (findBestMatch of B_j: pose
K_j), the object too (M_j), and the object goes where the demonstration put it relative to its
box: K_j T_j M_j^-1. A box looks the same turned by its symmetry (:data:`BOX_SYMMETRY`), so the
truth judges the object's pose on its box up to that turn: within :data:`TOLERANCE_M` at the
object's centre and :data:`TOLERANCE_DEG`.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from vslsp.errors import TaskFailed, VslspError
from vslsp.experiments.cloud_reproduction import Reproduction, reproduce, world_of
from vslsp.experiments.table_cleaning import (
    TOLERANCE_DEG,
    TOLERANCE_M,
    RobotOperation,
    film,
    picture,
    pose_error,
    say_outcome,
)
from vslsp.experiments.vsl3d_slips import DemonstrationSlips
from vslsp.outcomes import NoMatch
from vslsp.sim.cloud_scene import BOXES
from vslsp.vsl3d.cloud import DepthCamera, Frame
from vslsp.vsl3d.matching import CloudMatch, find_best_match
from vslsp.vsl3d.pictures import cloud_view, draw_frame, trial_clouds, trial_pictures
from vslsp.vsl3d.vsl import FRAME_MARGIN, CloudObservation, MovedObject, WorldCloud, euclidean_clusters
from vslsp.worlds.rgbd_table import RgbdTable, random_layout

OPERATIONS = (("duck", "box1"), ("teddy", "box2"))  # each object goes on top of its box
BOX_SYMMETRY = {"box1": 2, "box2": 4}  # turns about the vertical under which a box looks the same
MAX_TURN = np.radians(60.0)  # objects are seen again from about the same side
# A box and the object stacked on it are seen whole (the tallest stack: box2 and the teddy), and a
# box, turned any way, keeps 1.5 cm from what stands beside it (its half-diagonal and a margin):
# a box touching the other box or an object is segmented with it into one landmark.
STACK_HEIGHTS = dict.fromkeys(BOXES, 0.17)
BOX_RADII = {box: float(np.hypot(*size[:2])) / 2.0 + 0.015 for box, size in BOXES.items()}
SEGMENT_GAP = 0.008


@dataclass(frozen=True)
class StackResult(RobotOperation):
    """One stacking operation (errors against the truth, relative to the box)."""

    index: int
    moved: str
    box: str
    demonstration: dict | None
    execution: dict | None = None
    landmark_fitness: float | None = None
    picked: str | None = None
    final_error_mm: float | None = None
    final_error_deg: float | None = None  # the turn about the vertical
    final_rotation_deg: float | None = None  # the whole rotation (reported, not judged)
    error: str | None = None
    extra: dict = field(default_factory=dict)  # with --tutor-slips: the slip's record

    def to_dict(self) -> dict:
        data = {
            k: getattr(self, k)
            for k in (
                "index",
                "moved",
                "box",
                "demonstration",
                "landmark_fitness",
                "picked",
                "final_error_mm",
                "final_error_deg",
                "final_rotation_deg",
                "error",
            )
        }
        return self._record({**data, **self.extra})


def landmark_under(pre: WorldCloud, moved: MovedObject) -> CloudObservation:
    """The segment of the pre-action cloud under the object's post-action observation: the box
    the tutor put it on (raises :class:`TaskFailed` when nothing is there)."""
    post = moved.post
    lower, upper = post.frame.lower, post.frame.upper
    below = (
        (pre.points[:, 0] >= lower[0])
        & (pre.points[:, 0] <= upper[0])
        & (pre.points[:, 1] >= lower[1])
        & (pre.points[:, 1] <= upper[1])
        & (pre.points[:, 2] < post.points[:, 2].min() + 0.005)
    )
    if below.sum() < 50:
        raise TaskFailed(
            "no landmark under the placed object: the tutor put it on the table, not on a box",
            cause="no landmark under the placed object",
        )
    labels = euclidean_clusters(pre.points, SEGMENT_GAP)
    label = np.bincount(labels[below]).argmax()
    points = pre.points[labels == label]
    return CloudObservation(points, Frame.around(points, FRAME_MARGIN), pre.viewpoint_at(points))


def relative_error(
    scene: RgbdTable, name: str, box: str, goal_object: np.ndarray, goal_box: np.ndarray
) -> tuple[float, float, float]:
    """The object's pose on its box against the demonstrated one, up to the box's symmetry
    (:func:`~vslsp.experiments.table_cleaning.pose_error`'s mm, turn and rotation)."""
    lower, upper = scene.bounds(name)
    errors = []
    for k in range(BOX_SYMMETRY[box]):
        turn = np.eye(4)
        angle = 2.0 * np.pi * k / BOX_SYMMETRY[box]
        turn[:2, :2] = [[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]]
        goal = scene.truth(box) @ turn @ np.linalg.inv(goal_box) @ goal_object
        errors.append(pose_error(goal, scene.truth(name), (lower + upper) / 2.0))
    return min(errors, key=lambda e: e[0] / (TOLERANCE_M * 1000) + e[1] / TOLERANCE_DEG)


def run_stacking(
    seed: int = 0,
    method: str = "prerejective_ransac",
    absent: tuple[str, ...] = (),
    video: Any = None,
    views: int = 1,
    tutor_slips: float | None = None,
    slip_detection: bool = True,
    recording: Any = None,
) -> tuple[tuple[StackResult, ...], dict]:
    """Demonstrate the two stacks in a seeded random scene, move everything, reproduce with the
    robot. ``absent`` names objects or boxes left out of the new scene (bad input: each is
    diagnosed, the other operations still run); ``views``: the RGB-D sensors whose clouds are
    fused (1, the paper's single view, or 2). ``tutor_slips``: the probability that the tutor
    also nudges another object still on the table in an operation (None: the option not given),
    found or not by the ``slip_detection`` (:mod:`vslsp.experiments.vsl3d_slips`; the landmark
    is the box under the operated object's post-action observation, never a disturbed object).
    ``recording``: a :class:`~vslsp.sim.rerun_log.RerunLog` that logs both scenes. Returns the results
    and the report's pictures."""
    rng = np.random.default_rng(seed)
    names = [name for name, _ in OPERATIONS] + list(BOXES)
    layout = random_layout(names, seed, tray=False, heights=STACK_HEIGHTS, radii=BOX_RADII)
    objects = {name: layout[name] for name, _ in OPERATIONS}
    boxes = {box: layout[box] for box in BOXES}
    demonstrated: list[tuple[MovedObject, CloudObservation] | str] = []
    goals: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    images = []
    slips = DemonstrationSlips(tutor_slips, seed, slip_detection)
    with RgbdTable(objects, tray=False, robot=True, boxes=boxes, views=views) as scene:
        film(scene, video, "stacking: the tutor's demonstration", recording)
        for index, (name, box) in enumerate(OPERATIONS):
            scene.say(f"the tutor stacks {name} on {box}")
            scene.park()
            pre_image = scene.capture()
            x, y = scene.truth(box)[:2, 3]
            yaw = layout[name][2] + rng.uniform(-MAX_TURN, MAX_TURN)
            start = scene.bounds(name)
            scene.tutor_move(name, scene.resting_pose(name, x, y, yaw, support=BOXES[box][2]))
            scene.settle()
            stacked = [n for n, _ in OPERATIONS[: index + 1]]  # the objects on their boxes by now
            slips.during(scene, index, [n for n, _ in OPERATIONS if n not in stacked], [start])
            post_image = scene.capture()
            goals[name] = (scene.truth(name), scene.truth(box))
            try:
                pre = world_of(pre_image)
                moved = slips.get_object(pre, world_of(post_image), method, seed)
                landmark = landmark_under(pre, moved)
                demonstrated.append((moved, landmark))
                slips.found[index] = slips.record(scene, moved, moved.to_dict())
                camera = DepthCamera.of(pre_image.camera)
                pre_rgb, post_rgb = slips.picture(pre_image.rgb, post_image.rgb, camera, scene, moved)
                images.append(
                    np.hstack(
                        [
                            draw_frame(
                                draw_frame(pre_rgb, camera, moved.pre.frame, (255, 0, 0)),
                                camera,
                                landmark.frame,
                                (0, 0, 255),
                            ),
                            draw_frame(post_rgb, camera, moved.post.frame, (0, 160, 0)),
                        ]
                    )
                )
            except VslspError as error:
                demonstrated.append(f"demonstration: {error}")
        scene.park()
        demonstrated_final = scene.picture()
    moved_layout = random_layout(names, seed + 1, tray=False, heights=STACK_HEIGHTS, radii=BOX_RADII)
    objects = {
        name: (*moved_layout[name][:2], layout[name][2] + rng.uniform(-MAX_TURN, MAX_TURN))
        for name, _ in OPERATIONS
        if name not in absent
    }
    boxes = {box: moved_layout[box] for box in BOXES if box not in absent}
    results: list[StackResult] = []
    matched, cloud, records = [], None, {}
    with RgbdTable(objects, tray=False, robot=True, boxes=boxes, views=views) as scene:
        film(scene, video, "stacking: the robot reproduces the stacks (VSL-3D)", recording)
        movable = list(scene.bodies.values())
        put_down: list[np.ndarray] = []  # where earlier operations put their objects
        for index, ((name, box), demo) in enumerate(zip(OPERATIONS, demonstrated, strict=True)):
            if isinstance(demo, str):
                results.append(StackResult(index, name, box, None, error=demo, extra=slips.extra(index)))
                continue
            moved, landmark = demo
            found: dict[str, CloudMatch] = {}  # the landmark in the attempt's capture

            def landmarks(world, landmark=landmark, box=box, found=found):
                missing = f"landmark {box} not found in the new scene"
                try:
                    match = find_best_match(world, landmark, method=method, seed=seed)
                except VslspError as error:
                    raise TaskFailed(f"{missing}: {error}", cause=missing) from error
                if isinstance(match, NoMatch):
                    raise TaskFailed(f"{missing}: no match: {match.reason}", cause=missing)
                found["box"] = match
                return match.points  # the object is not looked for on its landmark

            def motion_for(match, world, moved=moved, found=found):
                # K_j T_j M_j^-1: the demonstrated motion, carried along with the box.
                return (
                    found["box"].registration.transform @ moved.transform @ np.linalg.inv(match.registration.transform)
                )

            scene.say(f"robot, operation {index + 1}: {name} onto {box} (both found in the point cloud)")
            record = reproduce(
                scene,
                moved.pre,
                motion_for,
                method=method,
                seed=seed,
                movable=movable,
                placed=tuple(put_down),
                landmarks=landmarks,
            )
            fitness = found["box"].registration.fitness if "box" in found else None
            summary = slips.found[index]
            results.append(judge_stack(scene, index, name, box, summary, record, goals[name], fitness))
            results[-1] = replace(results[-1], extra=slips.extra(index))
            say_outcome(scene, index, results[-1])
            if record.placed is not None:
                put_down.append(record.placed)
            matched.append(picture(record))
            records[index] = record
            if cloud is None and record.last is not None:
                cloud = cloud_view(record.last.world.points)
        scene.park()
        clouds = trial_clouds([None if isinstance(d, str) else d[0] for d in demonstrated], records)
        pictures = trial_pictures(images, matched, cloud, demonstrated_final, scene.picture(), clouds)
    return tuple(results), pictures


def judge_stack(
    scene: RgbdTable,
    index: int,
    name: str,
    box: str,
    summary: dict,
    record: Reproduction,
    goal: tuple[np.ndarray, np.ndarray],
    fitness: float | None,
) -> StackResult:
    picked = next((a.held for a in reversed(record.attempts) if a.held is not None), None)
    errors: tuple[float | None, float | None, float | None] = (None, None, None)
    if record.attempts and name in scene.bodies and box in scene.bodies:
        errors = relative_error(scene, name, box, *goal)
    return StackResult(
        index,
        name,
        box,
        summary,
        record.to_dict(),
        None if fitness is None else round(fitness, 4),
        picked,
        *errors,
        error=record.diagnosis,
    )
