"""The table-cleaning experiment of VSL-3D (paper, section "VSL-3D", "Table Cleaning": "the
goal is to clean up the table by picking objects and placing two of them inside the empty box
and the final one in front of the box according to the demonstration ... Before the
reproduction phase starts, the objects are reshuffled randomly").

Demonstration (Algorithm 1, part I): for each operation the tutor moves one object while the
RGB-D sensor captures the pre- and post-action worlds; :func:`get_object` finds the object, its
pre-/post-action observations and its motion T_i (4x4). Reproduction (part II): in the
reshuffled world, :func:`find_best_match` finds each recorded pre-action observation (pose
M_j); the object must go where the demonstration put it, so it is moved by T_j M_j^-1. A
stand-in for the robot's pick-and-place takes the object under the match and applies that
motion; the simulator's ground truth then says how close each object came to its demonstrated
final pose. Perception never reads the ground truth.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import cv2
import numpy as np

from vslsp.errors import VslspError
from vslsp.sim.cloud_scene import TRAY_POSITION, CloudScene, RGBDImage, random_layout
from vslsp.vsl3d.cloud import DepthCamera, Frame
from vslsp.vsl3d.registration import transform_error
from vslsp.vsl3d.matching import find_best_match
from vslsp.vsl3d.vsl import MovedObject, WorldCloud, get_object

WORKSPACE = Frame((0.25, -0.40, 0.006), (0.90, 0.40, 0.40))  # the world: above the table top
# The demonstration: two objects into the box, the last in front of it (nearer the sensor).
OPERATIONS = (("duck", (TRAY_POSITION[0], TRAY_POSITION[1] - 0.055), True),
              ("teddy", (TRAY_POSITION[0], TRAY_POSITION[1] + 0.055), True),
              ("duckling", (TRAY_POSITION[0] - 0.20, TRAY_POSITION[1] - 0.03), False))
MAX_TURN = np.radians(60.0)  # a single view records one side: reshuffles keep it in view
TOLERANCE_M, TOLERANCE_DEG = 0.005, 3.0


@dataclass(frozen=True)
class OperationResult:
    """One operation: what the demonstration saw and how the reproduction did (errors against
    the simulator's truth; ``error`` says why a step failed)."""

    index: int
    moved: str  # the object the tutor moved (truth, for the report)
    demonstration: dict | None
    found_at: list[float] | None = None
    match_fitness: float | None = None
    picked: str | None = None
    final_error_mm: float | None = None
    final_error_deg: float | None = None
    error: str | None = None

    def to_dict(self) -> dict:
        return {**asdict(self), "success": self.success}

    @property
    def success(self) -> bool:
        return (self.error is None and self.picked == self.moved and self.final_error_mm is not None
                and self.final_error_mm < TOLERANCE_M * 1000 and self.final_error_deg < TOLERANCE_DEG)


@dataclass(frozen=True)
class TableCleaningResult:
    seed: int
    method: str
    operations: tuple[OperationResult, ...]

    @property
    def success(self) -> bool:
        return all(operation.success for operation in self.operations)

    def to_dict(self) -> dict:
        return {"experiment": "table-cleaning", "seed": self.seed, "method": self.method, "success": self.success,
                "operations": [op.to_dict() for op in self.operations]}


def _world(image: RGBDImage) -> WorldCloud:
    return WorldCloud.capture(image.depth, DepthCamera.of(image.camera), WORKSPACE)


def draw_frame(rgb: np.ndarray, camera: DepthCamera, frame: Frame, colour: tuple[int, int, int]) -> np.ndarray:
    """The RGB image (H, W, 3) with the frame's cuboid drawn on it."""
    corners = np.array([[x, y, z] for x in (frame.lower[0], frame.upper[0]) for y in (frame.lower[1], frame.upper[1])
                        for z in (frame.lower[2], frame.upper[2])])
    uv, _ = camera.project(corners)
    image = np.ascontiguousarray(rgb.copy())
    for a in range(8):
        for b in range(a + 1, 8):
            if bin(a ^ b).count("1") == 1:  # corners differing in one coordinate share an edge
                cv2.line(image, tuple(int(v) for v in uv[a]), tuple(int(v) for v in uv[b]), colour, 1, cv2.LINE_AA)
    return image


def run_table_cleaning(seed: int = 0, method: str = "prerejective_ransac"
                       ) -> tuple[TableCleaningResult, list[np.ndarray], np.ndarray]:
    """Demonstrate the table cleaning in a seeded random scene, reshuffle, reproduce. Returns the
    outcome, the demonstration's pre|post RGB images (H, 2W, 3) with the found object's frame,
    and the final RGB view (H, W, 3)."""
    rng = np.random.default_rng(seed)
    names = [name for name, _, _ in OPERATIONS] + ["blob"]  # the blob stays on the table
    layout = random_layout(names, seed)
    demonstrated: list[tuple[MovedObject | None, str | None]] = []
    goals: dict[str, np.ndarray] = {}
    images: list[np.ndarray] = []
    with CloudScene(layout) as scene:
        for name, (x, y), into_tray in OPERATIONS:
            pre_image = scene.capture()
            support = scene.surface_height(x, y) if into_tray else 0.0
            yaw = layout[name][2] + rng.uniform(-MAX_TURN, MAX_TURN)
            scene.tutor_move(name, scene.resting_pose(name, x, y, yaw, support=support))
            post_image = scene.capture()
            goals[name] = scene.pose(name)
            try:
                moved = get_object(_world(pre_image), _world(post_image), method=method, seed=seed)
                demonstrated.append((moved, None))
                camera = DepthCamera.of(pre_image.camera)
                images.append(np.hstack([draw_frame(pre_image.rgb, camera, moved.pre.frame, (255, 0, 0)),
                                         draw_frame(post_image.rgb, camera, moved.post.frame, (0, 160, 0))]))
            except VslspError as error:
                demonstrated.append((None, str(error)))
    reshuffled = random_layout(names, seed + 1)
    reshuffled = {name: (x, y, layout[name][2] + rng.uniform(-MAX_TURN, MAX_TURN))
                  for name, (x, y, _) in reshuffled.items()}
    results = []
    with CloudScene(reshuffled) as scene:
        for index, ((name, _, _), (moved, failure)) in enumerate(zip(OPERATIONS, demonstrated)):
            if moved is None:
                results.append(OperationResult(index, name, None, error=failure))
                continue
            summary = moved.to_dict()
            try:
                match = find_best_match(_world(scene.capture()), moved.pre, method=method, seed=seed)
            except VslspError as error:
                results.append(OperationResult(index, name, summary, error=str(error)))
                continue
            picked = scene.object_at(match.position)
            errors: tuple[float | None, float | None] = (None, None)
            if picked is not None:
                # The robot's stand-in: move what lies under the match by T_j M_j^-1.
                motion = moved.transform @ np.linalg.inv(match.registration.transform)
                scene.tutor_move(picked, motion @ scene.pose(picked))
                if picked == name:  # how far from the demonstrated pose, at the object's centre
                    lower, upper = scene.bounds(picked)
                    offset, turn = transform_error(goals[name] @ np.linalg.inv(scene.pose(picked)), np.eye(4),
                                                   (lower + upper) / 2.0)
                    errors = (round(offset * 1000, 3), round(turn, 3))
            result = OperationResult(index, name, summary, match.position.tolist(), match.registration.fitness,
                                     picked, *errors)
            results.append(result)
        final = scene.capture().rgb
    return TableCleaningResult(seed, method, tuple(results)), images, final
