"""Closed-loop execution: perceive the scene, run a skill on an object, verify its effect.

Paper section "Results" of VSL-SP: each plan step is executed by a learned skill; after
every step the robot observes again, grounds ``far`` for every object, and checks the
expected effect. Perception goes through the camera only: the object's place on the table
comes from its pixel centroid and the camera's pixel -> table mapping, the push direction
from the landmark line seen in the image.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from vslsp.errors import TaskFailed, UnreachableError, VslspError
from vslsp.skills.execute import execute_skill
from vslsp.skills.library import SkillLibrary
from vslsp.sim import TABLE_Z, CUBE_SIZE
from vslsp.sim.robot import HandTrajectory
from vslsp.grounding.operation import SceneGrounding, ground_scene


@dataclass(frozen=True)
class PerceivedObject:
    """An object as the robot sees it: symbol, pixel centroid, place on the table, (far b)."""

    name: str
    pixel: tuple[float, float]
    table_xy: tuple[float, float]
    far: bool


@dataclass(frozen=True)
class PerceivedState:
    """One observation grounded: objects by symbol, and the landmark's normal on the table."""

    objects: dict[str, PerceivedObject]
    normal: np.ndarray  # (2,) unit, pointing away from the robot
    line_point: np.ndarray  # (2,) a point of the line on the table (m)
    grounding: SceneGrounding = field(repr=False)
    image: np.ndarray = field(repr=False)

    def line_distance(self, name: str) -> float:
        """The object's distance (m) to the line on the table, signed: positive on the far side."""
        return float(np.dot(np.asarray(self.objects[name].table_xy) - self.line_point, self.normal))

    def far(self) -> dict[str, bool]:
        return {name: obj.far for name, obj in self.objects.items()}

    def to_dict(self) -> dict:
        return {name: {"far": o.far, "pixel": [round(v, 1) for v in o.pixel],
                       "table_xy": [round(v, 4) for v in o.table_xy]} for name, o in self.objects.items()}


def perceive(world, camera: str = "head") -> PerceivedState:
    """Observe the scene with ``camera`` and ground every object (the arm is parked first)."""
    observation = world.observe(camera)
    grounding = ground_scene(observation.rgb, robot_side="bottom")
    view = observation.camera
    objects = {}
    for name, obj in zip(grounding.far_by_name(), grounding.objects):
        far = grounding.far_by_name()[name]
        # The centroid of the visible faces lies about half-way up the cube.
        xy = view.pixel_to_table(*obj.centroid, z=TABLE_Z + CUBE_SIZE / 2)
        objects[name] = PerceivedObject(name, tuple(obj.centroid), xy, far)
    line = grounding.landmark
    ends = np.array([view.pixel_to_table(*line.p1), view.pixel_to_table(*line.p2)])
    direction = ends[1] - ends[0]
    normal = np.array([-direction[1], direction[0]]) / np.linalg.norm(direction)
    if np.dot(normal, ends[0]) < 0:  # the robot stands at the origin: far is away from it
        normal = -normal
    return PerceivedState(objects, normal, ends.mean(axis=0), grounding, observation.rgb)


@dataclass(frozen=True)
class StepResult:
    """One executed plan step: what was done, what was expected and seen, the hand's path."""

    action: str
    obj: str
    expected_far: bool
    observed_far: bool | None
    ok: bool
    error: str | None
    trajectory: HandTrajectory | None = field(default=None, repr=False)

    def to_dict(self) -> dict:
        return {"action": self.action, "object": self.obj, "expected_far": self.expected_far,
                "observed_far": self.observed_far, "ok": self.ok, "error": self.error}


EXPECTED_FAR = {"push": True, "pull": False}


def execute_step(world, library: SkillLibrary, action: str, obj: str, state: PerceivedState,
                 fault: str | None = None) -> tuple[StepResult, PerceivedState]:
    """Run ``action`` on ``obj`` as perceived in ``state``; observe again and check the effect.

    ``fault`` injects an execution fault for testing replanning: ``"nudge"`` (the tutor puts
    the cube back where it was after the action) or ``"skip"`` (the step is not executed).
    """
    if action not in EXPECTED_FAR:
        raise TaskFailed(f"no skill for action {action!r}; the robot knows {sorted(EXPECTED_FAR)}")
    if obj not in state.objects:
        raise TaskFailed(f"the plan acts on {obj!r} but the robot does not see it (it sees {sorted(state.objects)})")
    target = state.objects[obj]
    trajectory, error = None, None
    if fault != "skip":
        before = _truth_pose(world, obj)
        try:
            trajectory = execute_skill(world, library[action], np.array(target.table_xy), state.normal,
                                       state.line_distance(obj))
        except UnreachableError as unreachable:
            error = str(unreachable)
        if fault == "nudge" and before is not None:
            world.tutor.relocate(*before)
    new_state = perceive(world)
    observed = new_state.objects.get(obj)
    observed_far = observed.far if observed is not None else None
    ok = error is None and observed_far == EXPECTED_FAR[action]
    if error is None and not ok:
        error = (f"expected (far {obj}) to be {EXPECTED_FAR[action]} after {action}, observed "
                 f"{'nothing' if observed is None else observed_far}")
    return StepResult(action, obj, EXPECTED_FAR[action], observed_far, ok, error, trajectory), new_state


def _truth_pose(world, colour: str):
    """For fault injection only (the tutor's hand, not the robot's perception)."""
    for cube in world.spec.cubes:
        if cube.colour == colour:
            x, y, yaw = world.cube_pose(cube.name)
            return cube.name, x, y, yaw
    return None


__all__ = ["PerceivedObject", "PerceivedState", "StepResult", "execute_step", "perceive", "VslspError"]
