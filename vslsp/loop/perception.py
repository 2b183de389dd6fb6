"""Perceiving the scene: one camera image grounded into the objects the robot can act on.

Paper section "Results" of VSL-SP: after every step the robot observes again and grounds
``far`` for every object. Perception goes through the camera only: the object's place on the
table comes from its pixel centroid and the camera's pixel -> table mapping, the push
direction from the landmark line seen in the image.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from vslsp.grounding.operation import SceneGrounding, ground_scene
from vslsp.sim import CUBE_SIZE, TABLE_Z, Observation
from vslsp.stages import in_stage
from vslsp.worlds import World


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
        return {
            name: {"far": o.far, "pixel": [round(v, 1) for v in o.pixel], "table_xy": [round(v, 4) for v in o.table_xy]}
            for name, o in self.objects.items()
        }


@in_stage("perception")
def perceive(world: World[Observation]) -> PerceivedState:
    """Observe the scene with the world's sensor (the head camera) and ground every object (the
    arm is parked, out of view, between steps)."""
    observation = world.observe()
    grounding = ground_scene(observation.rgb, robot_side="bottom")
    view = observation.camera
    objects = {}
    for name, obj in zip(grounding.far_by_name(), grounding.objects):
        far = grounding.far_by_name()[name]
        # The centroid of the visible faces lies about half-way up the cube.
        xy = view.pixel_to_table(*obj.centroid, z=TABLE_Z + CUBE_SIZE / 2)
        objects[name] = PerceivedObject(name, (float(obj.centroid[0]), float(obj.centroid[1])), xy, far)
    line = grounding.landmark
    ends = np.array([view.pixel_to_table(*line.p1), view.pixel_to_table(*line.p2)])
    direction = ends[1] - ends[0]
    normal = np.array([-direction[1], direction[0]]) / np.linalg.norm(direction)
    if np.dot(normal, ends[0]) < 0:  # the robot stands at the origin: far is away from it
        normal = -normal
    return PerceivedState(objects, normal, ends.mean(axis=0), grounding, observation.rgb)
