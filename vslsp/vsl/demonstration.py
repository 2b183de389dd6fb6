"""The demonstration recorder: Algorithm 1, part I, of the paper.

For each operation i the tutor performs, VSL keeps the pre- and post-action observations
O^Pre(i), O^Post(i) (the observation dictionaries), the moved object's symbol B_i, its poses
P^Pre_i, P^Post_i and SIFT features φ_i (``getObject``), the constraints C^Pre_i, C^Post_i on
(far B_i) relative to the landmark L (``getConstraint``) and the action Π_i (``getAction``).

On disk a demonstration is a folder: ``demonstration.json`` (everything but pixels and
descriptors), ``pre_01.png``/``post_01.png``... (the observations) and ``features.npz`` (φ,
read with ``allow_pickle=False``). No pickle anywhere.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from vslsp.errors import InputError
from vslsp.grounding.operation import Grounding, ground
from vslsp.grounding.spatial import check_robot_side
from vslsp.vision.features import Features, object_features
from vslsp.vision.image import as_rgb, read_image, write_image
from vslsp.vision.landmark import Line, find_landmark

FORMAT = "vslsp-demonstration/1"


@dataclass(frozen=True)
class Pose:
    """An object's pose in an observation: (x, y) px and θ (rad, image coordinates)."""

    x: float
    y: float
    theta: float

    def to_dict(self) -> dict:
        return {"x": round(self.x, 2), "y": round(self.y, 2), "theta": round(self.theta, 5)}

    @classmethod
    def from_dict(cls, data: dict) -> Pose:
        return cls(float(data["x"]), float(data["y"]), float(data["theta"]))


@dataclass(frozen=True, eq=False)
class Operation:
    """Operation i: observations (H, W, 3) uint8, the grounding (B_i, C^Pre_i, C^Post_i, Π_i),
    poses P^Pre_i, P^Post_i, the object's size (px) and its features φ_i (pre observation)."""

    pre_observation: np.ndarray
    post_observation: np.ndarray
    grounding: Grounding
    pose_pre: Pose
    pose_post: Pose
    object_size: float
    features: Features

    @property
    def symbol(self) -> str:
        return self.grounding.name

    @property
    def action(self) -> str | None:
        return self.grounding.action

    @property
    def constraints_pre(self) -> dict[str, bool]:
        return {"far": self.grounding.far_pre}

    @property
    def constraints_post(self) -> dict[str, bool]:
        return {"far": self.grounding.far_post}


@dataclass(frozen=True, eq=False)
class Demonstration:
    """A recorded demonstration: the landmark L, the operations in order, the robot's side."""

    landmark: Line
    operations: tuple[Operation, ...]
    robot_side: str = "bottom"

    @property
    def pre_observations(self) -> tuple[np.ndarray, ...]:
        """O^Pre: the pre-action observations, in order."""
        return tuple(op.pre_observation for op in self.operations)

    @property
    def post_observations(self) -> tuple[np.ndarray, ...]:
        """O^Post: the post-action observations, in order."""
        return tuple(op.post_observation for op in self.operations)

    @property
    def policy(self) -> tuple[str | None, ...]:
        """Π: the identified actions, in order."""
        return tuple(op.action for op in self.operations)

    def save(self, folder: str | Path) -> Path:
        """Write the demonstration into ``folder`` (created); returns the JSON file's path."""
        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        arrays: dict[str, np.ndarray] = {}
        records = []
        for i, op in enumerate(self.operations, start=1):
            pre_file, post_file = f"pre_{i:02d}.png", f"post_{i:02d}.png"
            write_image(folder / pre_file, op.pre_observation)
            write_image(folder / post_file, op.post_observation)
            arrays.update(op.features.to_arrays(f"op{i:02d}"))
            records.append(
                {
                    "grounding": op.grounding.to_dict(),
                    "pose_pre": op.pose_pre.to_dict(),
                    "pose_post": op.pose_post.to_dict(),
                    "object_size": op.object_size,
                    "pre_observation": pre_file,
                    "post_observation": post_file,
                }
            )
        np.savez(folder / "features.npz", **arrays)  # type: ignore[arg-type]
        path = folder / "demonstration.json"
        path.write_text(
            json.dumps(
                {
                    "format": FORMAT,
                    "robot_side": self.robot_side,
                    "landmark": self.landmark.to_dict(),
                    "policy": list(self.policy),
                    "operations": records,
                },
                indent=2,
            )
            + "\n"
        )
        return path

    @classmethod
    def load(cls, folder: str | Path) -> Demonstration:
        """Read a demonstration written by :meth:`save`."""
        folder = Path(folder)
        path = folder / "demonstration.json"
        try:
            data = json.loads(path.read_text())
            if data.get("format") != FORMAT:
                raise KeyError(f"format is {data.get('format')!r}, expected {FORMAT!r}")
            with np.load(folder / "features.npz", allow_pickle=False) as arrays:
                operations = tuple(
                    Operation(
                        pre_observation=read_image(folder / record["pre_observation"]),
                        post_observation=read_image(folder / record["post_observation"]),
                        grounding=Grounding.from_dict(record["grounding"], data["robot_side"]),
                        pose_pre=Pose.from_dict(record["pose_pre"]),
                        pose_post=Pose.from_dict(record["pose_post"]),
                        object_size=float(record["object_size"]),
                        features=Features.from_arrays(arrays, f"op{i:02d}"),
                    )
                    for i, record in enumerate(data["operations"], start=1)
                )
            return cls(Line.from_dict(data["landmark"]), operations, data["robot_side"])
        except (OSError, ValueError, KeyError, TypeError) as error:
            raise InputError(
                f"cannot read the demonstration in {folder}: {error}; "
                "record it again with DemonstrationRecorder(...).demonstration().save()"
            ) from error


class DemonstrationRecorder:
    """Records a demonstration operation by operation (Algorithm 1, part I).

    ``recorder = DemonstrationRecorder(first_image)`` detects the landmark L (line 2);
    ``recorder.record(pre, post)`` adds one operation (lines 5-9);
    ``recorder.demonstration()`` gives the recorded :class:`Demonstration`.
    """

    def __init__(self, world: np.ndarray, robot_side: str = "bottom") -> None:
        self.robot_side = check_robot_side(robot_side)
        self.landmark = find_landmark(as_rgb(world, "world image"))
        self.operations: list[Operation] = []

    def record(self, pre: np.ndarray, post: np.ndarray) -> Operation:
        """Ground one operation from its pre- and post-action observations (H, W, 3) uint8."""
        grounding = ground(pre, post, self.robot_side)
        before, after = grounding.pre_object, grounding.post_object
        if before is None or after is None:
            raise InputError(
                "the moved object is not seen both before and after the operation; let the tutor "
                "move one object at a time, in the camera's view"
            )
        operation = Operation(
            pre_observation=np.array(pre, copy=True),
            post_observation=np.array(post, copy=True),
            grounding=grounding,
            pose_pre=Pose(float(before.centroid[0]), float(before.centroid[1]), float(np.radians(before.orientation))),
            pose_post=Pose(float(after.centroid[0]), float(after.centroid[1]), float(np.radians(after.orientation))),
            object_size=float(max(before.box[2], before.box[3])),
            features=object_features(pre, before.box),
        )
        self.operations.append(operation)
        return operation

    def demonstration(self) -> Demonstration:
        return Demonstration(self.landmark, tuple(self.operations), self.robot_side)
