"""The table-cleaning experiment of VSL-3D, executed by the robot (paper, section "VSL-3D",
"Table Cleaning": "the goal is to clean up the table by picking objects and placing two of them
inside the empty box and the final one in front of the box according to the demonstration ...
Before the reproduction phase starts, the objects are reshuffled randomly").

The world is physical (:class:`~vslsp.worlds.rgbd_table.RgbdTable`): objects settle under gravity
and the Franka Panda picks and places them. Demonstration (Algorithm 1, part I): for each
operation the tutor's hand moves one object while the RGB-D sensor captures the pre- and
post-action worlds; :func:`get_object` finds the object, its pre-/post-action observations and
its motion T_j (4x4). Reproduction (part II): in the reshuffled world the robot finds each
recorded pre-action observation (pose M_j), grasps the object where its matched cloud says, and
puts it down at T_j M_j^-1 (:mod:`vslsp.experiments.cloud_reproduction`). The simulator's ground truth then says
how close each object came to its demonstrated pose: within :data:`TOLERANCE_M` at its centre
and :data:`TOLERANCE_DEG` of turn about the vertical (a grasped object does not land as exactly
as a pose reset; the whole rotation, which includes how a released object settles, is reported).
Perception and grasping never read the ground truth.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from vslsp.errors import VslspError
from vslsp.experiments.cloud_reproduction import WORKSPACE, Reproduction, reproduce, world_of
from vslsp.experiments.vsl3d_slips import DemonstrationSlips, place_box
from vslsp.sim.cloud_scene import TRAY_POSITION
from vslsp.vsl3d.cloud import DepthCamera
from vslsp.vsl3d.pictures import cloud_view, draw_frame, draw_grasp, trial_clouds, trial_pictures
from vslsp.vsl3d.registration import transform_error
from vslsp.vsl3d.vsl import MovedObject
from vslsp.worlds.rgbd_table import RgbdTable, random_layout

__all__ = [
    "OPERATIONS",
    "TOLERANCE_DEG",
    "TOLERANCE_M",
    "WORKSPACE",
    "OperationResult",
    "RobotOperation",
    "TableCleaningResult",
    "run_table_cleaning",
]

# The demonstration: two objects into the box, the last in front of it (nearer the sensor).
OPERATIONS = (
    ("duck", (TRAY_POSITION[0], TRAY_POSITION[1] - 0.055), True),
    ("teddy", (TRAY_POSITION[0], TRAY_POSITION[1] + 0.055), True),
    ("duckling", (TRAY_POSITION[0] - 0.20, TRAY_POSITION[1] - 0.03), False),
)
# The blob stays on the table: it does not start near the places on the table where the
# demonstration puts an object down, in the demonstration or in the reshuffled scene (an object
# left next to the place is in the way of the object put there).
KEEP_CLEAR = {"blob": tuple(place for _, place, into_tray in OPERATIONS if not into_tray)}
MAX_TURN = np.radians(60.0)  # a single view records one side: reshuffles keep it in view
TOLERANCE_M, TOLERANCE_DEG = 0.015, 15.0


class RobotOperation:
    """What every VSL-3D operation record shares: success judged on the simulator's truth (the
    right object held, put down within :data:`TOLERANCE_M` and :data:`TOLERANCE_DEG`) and the
    JSON record with the robot's execution and the tolerances."""

    moved: str
    execution: dict | None
    picked: str | None
    final_error_mm: float | None
    final_error_deg: float | None
    error: str | None

    @property
    def success(self) -> bool:
        return (
            self.error is None
            and self.picked == self.moved
            and self.final_error_mm is not None
            and self.final_error_deg is not None
            and self.final_error_mm < TOLERANCE_M * 1000
            and self.final_error_deg < TOLERANCE_DEG
        )

    def _record(self, data: dict) -> dict:
        """``data`` (the operation's own fields) with the execution (or, when the robot never
        acted, an empty one with the error as diagnosis), the tolerances and the success."""
        execution = self.execution or {
            "executed_by": "robot",
            "attempts": 0,
            "grasp_outcome": [],
            "match_fitness": None,
            "grasp": None,
            "diagnosis": self.error,
        }
        return {
            **data,
            **execution,
            "tolerance_mm": TOLERANCE_M * 1000,
            "tolerance_deg": TOLERANCE_DEG,
            "success": self.success,
        }


@dataclass(frozen=True)
class OperationResult(RobotOperation):
    """One operation: what the demonstration saw and how the robot did (errors against the
    simulator's truth; ``error`` says why a step failed)."""

    index: int
    moved: str  # the object the tutor moved (truth, for the report)
    demonstration: dict | None
    execution: dict | None = None  # executed_by, attempts, grasp_outcome, match_fitness, grasp, diagnosis
    picked: str | None = None  # what the fingers held (truth)
    final_error_mm: float | None = None
    final_error_deg: float | None = None  # the turn about the vertical
    final_rotation_deg: float | None = None  # the whole rotation (reported, not judged)
    error: str | None = None
    extra: dict = field(default_factory=dict)  # with --tutor-slips: the slip's record

    def to_dict(self) -> dict:
        data = {key: value for key, value in asdict(self).items() if key not in ("execution", "extra")}
        return self._record({**data, **self.extra})


@dataclass(frozen=True)
class TableCleaningResult:
    seed: int
    method: str
    operations: tuple[OperationResult, ...]

    @property
    def success(self) -> bool:
        return all(operation.success for operation in self.operations)

    def to_dict(self) -> dict:
        return {
            "experiment": "table-cleaning",
            "seed": self.seed,
            "method": self.method,
            "success": self.success,
            "operations": [op.to_dict() for op in self.operations],
        }


def pose_error(goal: np.ndarray, pose: np.ndarray, centre: np.ndarray) -> tuple[float, float, float]:
    """How far ``pose`` (4, 4) is from ``goal`` (4, 4): mm at the object's ``centre`` (3,), the
    turn about the vertical (deg: the nearest rotation about z to the relative rotation) and the
    whole relative rotation's angle (deg; it includes how the object came to rest, which a
    released object decides itself: a teddy may settle leaning back less than the tutor stood it)."""
    offset, angle = transform_error(goal @ np.linalg.inv(pose), np.eye(4), centre)
    relative = goal[:3, :3] @ pose[:3, :3].T
    turn = abs(np.degrees(np.arctan2(relative[1, 0] - relative[0, 1], relative[0, 0] + relative[1, 1])))
    return round(offset * 1000, 3), round(float(turn), 3), round(angle, 3)


def tutor_operation(
    scene: RgbdTable, layout: dict, rng: np.random.Generator, index: int
) -> tuple[np.ndarray, np.ndarray]:
    """The tutor's operation ``index`` of :data:`OPERATIONS` in ``scene`` (of ``layout``): the
    object put down at its place (in the box: on the box's floor), turned from its layout's yaw
    by up to :data:`MAX_TURN` (drawn from ``rng``); the scene settles. Returns the object's
    bounds (lower (3,), upper (3,)) before it moved."""
    name, (x, y), into_tray = OPERATIONS[index]
    support = scene.surface_height(x, y) if into_tray else 0.0
    yaw = layout[name][2] + rng.uniform(-MAX_TURN, MAX_TURN)
    start = scene.bounds(name)
    scene.tutor_move(name, scene.resting_pose(name, x, y, yaw, support=support))
    scene.settle()
    return start


def demonstration_layout(seed: int) -> dict[str, tuple[float, float, float]]:
    """The demonstration's scene of ``seed``: the operated objects and the blob, which stays on the table."""
    names = [name for name, _, _ in OPERATIONS] + ["blob"]
    return random_layout(names, seed, keep_clear=KEEP_CLEAR)


def reshuffle(layout: dict, seed: int, rng: np.random.Generator) -> dict[str, tuple[float, float, float]]:
    """The reproduction's scene: the objects of ``layout`` laid out anew (the layout of
    ``seed + 1``), each turned from its demonstrated yaw by up to :data:`MAX_TURN` (drawn from ``rng``)."""
    reshuffled = random_layout(list(layout), seed + 1, keep_clear=KEEP_CLEAR)
    return {name: (x, y, layout[name][2] + rng.uniform(-MAX_TURN, MAX_TURN)) for name, (x, y, _) in reshuffled.items()}


def demonstrate(
    scene: RgbdTable,
    layout: dict,
    rng: np.random.Generator,
    method: str,
    seed: int,
    slips: DemonstrationSlips | None = None,
) -> tuple[list[tuple[MovedObject | None, str | None]], dict[str, np.ndarray], list[np.ndarray]]:
    """The tutor's operations in ``scene``: per operation getObject's result (or why it failed),
    the true goal poses, and the pre|post RGB pictures with the found frames. With ``slips`` the
    tutor may also nudge another object on the table (not one in the box) in each operation."""
    slips = slips or DemonstrationSlips(None, seed)
    demonstrated: list[tuple[MovedObject | None, str | None]] = []
    goals: dict[str, np.ndarray] = {}
    images: list[np.ndarray] = []
    in_box: list[str] = []
    for index, (name, _, into_tray) in enumerate(OPERATIONS):
        scene.say(f"the tutor moves {name}" + (" into the box" if into_tray else ""))
        scene.park()
        pre_image = scene.capture()
        start = tutor_operation(scene, layout, rng, index)
        in_box += [name] if into_tray else []
        later = [place_box(*place) for _, place, tray in OPERATIONS[index + 1 :] if not tray]
        slips.during(scene, index, [n for n in scene.bodies if n != name and n not in in_box], [start, *later])
        post_image = scene.capture()
        goals[name] = scene.truth(name)
        try:
            moved = slips.get_object(world_of(pre_image), world_of(post_image), method, seed)
            demonstrated.append((moved, None))
            slips.found[index] = slips.record(scene, moved, moved.to_dict())
            camera = DepthCamera.of(pre_image.camera)
            pre_rgb, post_rgb = slips.picture(pre_image.rgb, post_image.rgb, camera, scene, moved)
            images.append(
                np.hstack(
                    [
                        draw_frame(pre_rgb, camera, moved.pre.frame, (255, 0, 0)),
                        draw_frame(post_rgb, camera, moved.post.frame, (0, 160, 0)),
                    ]
                )
            )
        except VslspError as error:
            demonstrated.append((None, f"demonstration: {error}"))
    return demonstrated, goals, images


def film(scene: RgbdTable, video: Any, caption: str, recording: Any = None) -> None:
    """Let ``video`` (a :class:`~vslsp.sim.video.SceneVideo`, or None) film ``scene`` under ``caption``,
    and ``recording`` (a :class:`~vslsp.sim.rerun_log.RerunLog`, or None) log it."""
    if video is not None:
        video.attach(scene)
    if recording is not None:
        recording.attach(scene)
    if video is not None or recording is not None:
        scene.say(caption, hold=1.0)


def say_outcome(scene: RgbdTable, index: int, result: RobotOperation) -> None:
    """An operation's outcome in the video's caption, held a moment."""
    error = (
        f"{result.final_error_mm} mm, {result.final_error_deg} deg from the demonstrated pose"
        if result.final_error_mm is not None
        else (result.error or "")
    )
    scene.say(f"robot, operation {index + 1}: {'ok' if result.success else 'FAILED'}", error, hold=1.0)


def judge_operation(
    scene: RgbdTable,
    index: int,
    name: str,
    summary: dict,
    record: Reproduction,
    goal: np.ndarray,
    extra: dict | None = None,
) -> OperationResult:
    """The operation's result from the robot's record and the truth (``extra``: more fields of its record)."""
    picked = next((a.held for a in reversed(record.attempts) if a.held is not None), None)
    errors: tuple[float | None, float | None, float | None] = (None, None, None)
    if record.attempts:
        lower, upper = scene.bounds(name)
        errors = pose_error(goal, scene.truth(name), (lower + upper) / 2.0)
    return OperationResult(
        index, name, summary, record.to_dict(), picked, *errors, error=record.diagnosis, extra=extra or {}
    )


def run_table_cleaning(
    seed: int = 0,
    method: str = "prerejective_ransac",
    video: Any = None,
    views: int = 1,
    tutor_slips: float | None = None,
    slip_detection: bool = True,
    recording: Any = None,
) -> tuple[TableCleaningResult, dict[str, Any]]:
    """Demonstrate the table cleaning in a seeded random scene, reshuffle, reproduce with the
    robot. Returns the outcome and the report's pictures: ``demonstration`` (per operation the
    pre|post RGB (H, 2W, 3) with the found object's frame), ``matched`` (the reproduction's RGB
    views with the matched observation's frame and the grasp), ``cloud`` (the first
    reproduction capture's cloud coloured by segment) and ``final`` (the demonstrated final
    scene beside the reproduced one, (H, 2W, 3)). ``video``: a :class:`~vslsp.sim.video.SceneVideo`
    that films both scenes; ``views``: the RGB-D sensors whose clouds are fused (1, the paper's
    single view, or 2: the far sensor too). ``tutor_slips``: the probability that the tutor also nudges another
    object in an operation (None: the option not given), found or not by the ``slip_detection``
    (:mod:`vslsp.experiments.vsl3d_slips`). ``recording``: a :class:`~vslsp.sim.rerun_log.RerunLog` that
    logs both scenes and each reproduction's capture (its RGB image and its world cloud)."""
    rng = np.random.default_rng(seed)
    layout = demonstration_layout(seed)
    with RgbdTable(layout, robot=True, views=views) as scene:
        film(scene, video, "table cleaning: the tutor's demonstration", recording)
        slips = DemonstrationSlips(tutor_slips, seed, slip_detection)
        demonstrated, goals, images = demonstrate(scene, layout, rng, method, seed, slips)
        scene.park()
        demonstrated_final = scene.picture()
    reshuffled = reshuffle(layout, seed, rng)
    results, matched, cloud, records = [], [], None, {}
    with RgbdTable(reshuffled, robot=True, views=views) as scene:
        film(scene, video, "table cleaning: the robot reproduces it (VSL-3D)", recording)
        movable = list(scene.bodies.values())
        put_down: list[np.ndarray] = []  # where earlier operations put their objects
        for index, ((name, _, _), (moved, failure)) in enumerate(zip(OPERATIONS, demonstrated, strict=True)):
            if moved is None:
                results.append(OperationResult(index, name, None, error=failure, extra=slips.extra(index)))
                continue

            def motion_for(match, world, moved=moved):
                return moved.transform @ np.linalg.inv(match.registration.transform)  # T_j M_j^-1

            scene.say(f"robot, operation {index + 1}: {name} (found in the point cloud)")
            record = reproduce(
                scene, moved.pre, motion_for, method=method, seed=seed, movable=movable, placed=tuple(put_down)
            )
            summary = slips.found[index]
            results.append(judge_operation(scene, index, name, summary, record, goals[name], slips.extra(index)))
            say_outcome(scene, index, results[-1])
            if record.placed is not None:
                put_down.append(record.placed)
            matched.append(picture(record))
            records[index] = record
            if recording is not None and record.last is not None:
                recording.observation(f"robot, operation {index + 1}: {name}", record.last.image.rgb, scene.picture())
                recording.cloud("capture", record.last.world.points)
            if cloud is None and record.last is not None:
                cloud = cloud_view(record.last.world.points)
        scene.park()
        clouds = trial_clouds([moved for moved, _ in demonstrated], records)
        pictures = trial_pictures(images, matched, cloud, demonstrated_final, scene.picture(), clouds)
    return TableCleaningResult(seed, method, tuple(results)), pictures


def picture(record: Reproduction) -> np.ndarray:
    """The RGB view of the operation's last attempt with the matched observation's frame (red)
    and the grasp (yellow)."""
    attempt = record.last
    if attempt is None:
        return np.zeros((480, 640, 3), dtype=np.uint8)
    camera = DepthCamera.of(attempt.image.camera)
    image = attempt.image.rgb
    if attempt.match is not None:
        image = draw_frame(image, camera, attempt.match.frame, (255, 0, 0))
    if attempt.grasp is not None:
        image = draw_grasp(image, camera, attempt.grasp)
    return image
