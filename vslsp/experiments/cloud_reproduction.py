"""One operation of VSL-3D's reproduction executed by the robot (paper, Algorithm 1 part II:
``findBestMatch`` then ``executeAction``; section "VSL-3D": the object is moved by T_j M_j^-1).

:func:`reproduce` captures the world, finds the recorded pre-action observation in it (M_j),
plans the grasp from the matched cloud (:mod:`vslsp.vsl3d.grasping`), asks the caller for the
motion that takes the object to its goal (T_j M_j^-1 for the table cleaning, K_j T_j M_j^-1
relative to a landmark for the stacking), and has the Panda pick and place it. A grasp that
fails or an object that slips is seen in the next capture, which starts a second and last
attempt (gripping a little higher); an unreachable or ungraspable object is reported as such. Every failure is a
diagnosis in the record, never an exception. Neither an object the robot has already put where
an earlier operation wanted it nor a landmark is a candidate for the object of a later one:
the world within a centimetre of them is left out of the search for the object (a view of an
object turned far from its recorded pose can fit a box's corner better than the object itself).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from vslsp.errors import TaskFailed, VslspError
from vslsp.outcomes import Diagnosis, NoMatch
from vslsp.sim.cloud_scene import RGBDImage
from vslsp.sim.pick_place import PickPlaceResult
from vslsp.stages import in_stage, stage
from vslsp.vsl3d.cloud import DepthCamera, Frame
from vslsp.vsl3d.grasping import Grasp, place_for, plan_grasp
from vslsp.vsl3d.matching import CloudMatch, find_best_match
from vslsp.vsl3d.registration import transform_points
from vslsp.vsl3d.vsl import CloudObservation, WorldCloud
from vslsp.worlds.rgbd_table import FINGER_OPEN, RgbdTable

WORKSPACE = Frame((0.25, -0.40, 0.006), (0.90, 0.40, 0.40))  # the world: above the table top
MIN_WORLD_POINTS = 200  # fewer points above the table: the capture shows no object
RETRIED = (Diagnosis.GRASP_FAILED, Diagnosis.OBJECT_SLIPPED)
RETRY_HIGHER = 0.012  # m: the retry grips this much higher (a round body squeezes out of a low grip)


@in_stage("perception")
def world_of(image: RGBDImage) -> WorldCloud:
    """The world cloud of one capture, cut to :data:`WORKSPACE` (with several sensors, their
    clouds fused by the sensors' known poses)."""
    others = tuple((other.depth, DepthCamera.of(other.camera)) for other in image.others)
    return WorldCloud.capture(image.depth, DepthCamera.of(image.camera), WORKSPACE, others=others)


def check_world(world: WorldCloud) -> None:
    """Raise :class:`VslspError` with a diagnosis when the capture shows nothing to work on."""
    if len(world.points) < MIN_WORLD_POINTS:
        raise TaskFailed(
            f"empty capture: only {len(world.points)} points above the table in the workspace "
            "(all background); is the sensor looking at the table and are the objects on it?",
            cause="empty capture",
        )


@dataclass
class Attempt:
    """What one attempt saw and did (the artefacts for the report's pictures)."""

    image: RGBDImage
    world: WorldCloud
    match: CloudMatch | None = None
    grasp: Grasp | None = None
    outcome: str | None = None  # "held" or the pick-and-place diagnosis
    held: str | None = None  # what the fingers held (the simulator's truth, for the report)
    error: str | None = None
    placed: np.ndarray | None = None  # (N, 3) the matched points where the object was put, when held


@dataclass
class Reproduction:
    """An operation's record: the attempts and the final diagnosis (None: placed)."""

    attempts: list[Attempt] = field(default_factory=list)
    diagnosis: str | None = None

    @property
    def last(self) -> Attempt | None:
        return self.attempts[-1] if self.attempts else None

    @property
    def placed(self) -> np.ndarray | None:
        """The matched points (N, 3) where the object was put, when the last attempt held it
        to the end."""
        return self.last.placed if self.last is not None else None

    def to_dict(self) -> dict:
        last = self.last
        match = last.match if last is not None else None
        return {
            "executed_by": "robot",
            "attempts": len(self.attempts),
            "grasp_outcome": [a.outcome or a.error for a in self.attempts],
            "match_fitness": round(match.registration.fitness, 4) if match is not None else None,
            "found_at": np.round(match.position, 4).tolist() if match is not None else None,
            "grasp": last.grasp.to_dict() if last is not None and last.grasp is not None else None,
            "diagnosis": self.diagnosis,
        }


def reproduce(
    scene: RgbdTable,
    observation: CloudObservation,
    motion_for: Callable[[CloudMatch, WorldCloud], np.ndarray],
    *,
    method: str,
    seed: int,
    movable: list[int],
    placed: tuple[np.ndarray, ...] = (),
    landmarks: Callable[[WorldCloud], np.ndarray] | None = None,
) -> Reproduction:
    """Find ``observation`` in ``scene``'s capture, less what lies near the ``placed`` points
    (N, 3) each (objects earlier operations put down) and the landmarks' points (M, 3) that
    ``landmarks(world)`` finds, and move the object there by ``motion_for(match, world)`` (4, 4)
    with the robot, retrying once after a failed grasp."""
    record = Reproduction()
    for retry in range(2):
        with stage("execution"):
            scene.park()
        with stage("perception"):
            image = scene.capture()
            world = world_of(image)
        attempt = Attempt(image, world)
        record.attempts.append(attempt)
        try:
            with stage("perception"):
                check_world(world)
                avoid = [*placed, landmarks(world)] if landmarks is not None else list(placed)
                search = world.without(np.vstack(avoid)) if avoid else world
                found = find_best_match(search, observation, method=method, seed=seed)
            if isinstance(found, NoMatch):
                attempt.error = record.diagnosis = f"no match: {found.reason}"
                return record
            attempt.match = found
            with stage("planning"):
                attempt.grasp = plan_grasp(attempt.match.points, FINGER_OPEN, higher=RETRY_HIGHER * retry)
                motion = motion_for(attempt.match, world)
        except VslspError as error:
            attempt.error = record.diagnosis = str(error)
            return record
        with stage("execution"):
            result = execute_grasp(scene, attempt.grasp, motion, movable)
            scene.settle()
        attempt.outcome = "held" if result.ok else result.diagnosis
        attempt.held = result.held
        if result.ok:
            attempt.placed = transform_points(motion, attempt.match.points)
        record.diagnosis = result.diagnosis
        if result.diagnosis not in RETRIED:
            break
    return record


def execute_grasp(scene: RgbdTable, grasp: Grasp, motion: np.ndarray, movable: list[int]) -> PickPlaceResult:
    """Execute ``grasp`` and its place under ``motion`` (4, 4) with ``scene``'s Panda
    (:func:`~vslsp.vsl3d.grasping.place_for`); the fingers close on one of the ``movable`` bodies."""
    place, theta_place = place_for(grasp, motion)
    return scene.grasp_and_place(grasp.point, grasp.theta, place, theta_place, movable)
