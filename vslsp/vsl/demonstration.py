"""Demonstrations seen straight from above with a landmark: the image-plane observation model
of the :class:`~vslsp.vsl.recorder.Recorder` (Algorithm 1, part I, of the paper) and what it
records.

For each operation i the tutor performs, VSL keeps the pre- and post-action observations
O^Pre(i), O^Post(i) (the observation dictionaries), the moved object's symbol B_i, its poses
P^Pre_i, P^Post_i and SIFT features φ_i (``getObject``), the constraints C^Pre_i, C^Post_i on
(far B_i) relative to the landmark L (``getConstraint``) and the action Π_i (``getAction``);
given the pre-place observation (the world while the tutor holds the object), also the turn
the tutor gave the object (image subtraction and a window search over the angle).

On disk a demonstration is a folder: ``demonstration.json`` (everything but pixels and
descriptors), ``pre_01.png``/``post_01.png`` (and ``pre_place_01.png``)... (the observations)
and ``features.npz`` (φ, read with ``allow_pickle=False``). No pickle anywhere.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from vslsp.errors import InputError
from vslsp.files import load_npz, read_json
from vslsp.geometry.poses import wrap
from vslsp.grounding.operation import Grounding, ground
from vslsp.grounding.spatial import check_robot_side
from vslsp.outputs import atomic_file, write_text
from vslsp.vision.change import changed_pixels
from vslsp.vision.features import Features, object_features
from vslsp.vision.image import as_rgb, read_image, write_image
from vslsp.vision.landmark import Line, find_landmark
from vslsp.vision.parameters import DEFAULT_OBJECT_FINDING, ObjectFinding
from vslsp.vsl.recorder import Heights

FORMAT = "vslsp-demonstration/1"
MAX_RECORD_BYTES = 10_000_000  # demonstration.json
MAX_FEATURE_BYTES = 512_000_000  # features.npz, decoded (checked on its headers before loading)


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
    poses P^Pre_i, P^Post_i, the object's size (px) and its features φ_i (pre observation);
    when the world was seen while the tutor held the object, that pre-place observation
    (H, W, 3) and the turn (rad) the tutor gave the object."""

    pre_observation: np.ndarray
    post_observation: np.ndarray
    grounding: Grounding
    pose_pre: Pose
    pose_post: Pose
    object_size: float
    features: Features
    pre_place: np.ndarray | None = None
    turn: float | None = None

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
            record: dict = {
                "grounding": op.grounding.to_dict(),
                "pose_pre": op.pose_pre.to_dict(),
                "pose_post": op.pose_post.to_dict(),
                "object_size": op.object_size,
                "pre_observation": pre_file,
                "post_observation": post_file,
            }
            if op.pre_place is not None:
                record["pre_place_observation"] = pre_place_file = f"pre_place_{i:02d}.png"
                write_image(folder / pre_place_file, op.pre_place)
            if op.turn is not None:
                record["turn"] = op.turn
            records.append(record)
        with atomic_file(folder / "features.npz") as stream:
            np.savez(stream, **arrays)  # type: ignore[arg-type]
        path = folder / "demonstration.json"
        write_text(
            path,
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
            + "\n",
        )
        return path

    @classmethod
    def load(cls, folder: str | Path) -> Demonstration:
        """Read a demonstration written by :meth:`save`."""
        folder = Path(folder)
        path = folder / "demonstration.json"
        try:
            data = read_json(path, "demonstration", MAX_RECORD_BYTES)
            if data.get("format") != FORMAT:
                raise KeyError(f"format is {data.get('format')!r}, expected {FORMAT!r}")
            arrays = load_npz(folder / "features.npz", "demonstration's features", MAX_FEATURE_BYTES)
            operations = tuple(
                Operation(
                    pre_observation=read_image(folder / record["pre_observation"]),
                    post_observation=read_image(folder / record["post_observation"]),
                    grounding=Grounding.from_dict(record["grounding"], data["robot_side"]),
                    pose_pre=Pose.from_dict(record["pose_pre"]),
                    pose_post=Pose.from_dict(record["pose_post"]),
                    object_size=float(record["object_size"]),
                    features=Features.from_arrays(arrays, f"op{i:02d}"),
                    pre_place=(
                        read_image(folder / record["pre_place_observation"])
                        if "pre_place_observation" in record
                        else None
                    ),
                    turn=float(record["turn"]) if "turn" in record else None,
                )
                for i, record in enumerate(data["operations"], start=1)
            )
            return cls(Line.from_dict(data["landmark"]), operations, data["robot_side"])
        except (InputError, OSError, ValueError, KeyError, TypeError, AttributeError) as error:
            raise InputError(
                f"cannot read the demonstration in {folder}: {error}; "
                "record it again with Recorder(ImagePlane(...)).demonstration().save()"
            ) from error


class ImagePlane:
    """The observation model of images seen straight from above with a landmark line: poses in
    image pixels, (far b) relative to the landmark. ``ImagePlane(first_image)`` detects the
    landmark L (Algorithm 1 line 2); the :class:`~vslsp.vsl.recorder.Recorder` asks it for each
    operation (lines 7-9)."""

    def __init__(self, world: np.ndarray, robot_side: str = "bottom") -> None:
        self.robot_side = check_robot_side(robot_side)
        self.landmark = find_landmark(as_rgb(world, "world image"))

    def get_object(
        self, pre: np.ndarray, post: np.ndarray, pre_place: np.ndarray | None = None, heights: Heights | None = None
    ) -> Operation:
        """Ground one operation from its pre- and post-action observations (H, W, 3) uint8 (and
        its pre-place one, for the turn); ``heights`` are not needed (poses stay in pixels)."""
        grounding = self.ground_operation(pre, post)
        before, after = grounding.pre_object, grounding.post_object
        if before is None or after is None:
            raise InputError(
                "the moved object is not seen both before and after the operation; let the tutor "
                "move one object at a time, in the camera's view"
            )
        return Operation(
            pre_observation=pre,
            post_observation=post,
            grounding=grounding,
            pose_pre=Pose(float(before.centroid[0]), float(before.centroid[1]), float(np.radians(before.orientation))),
            pose_post=Pose(float(after.centroid[0]), float(after.centroid[1]), float(np.radians(after.orientation))),
            object_size=float(max(before.box[2], before.box[3])),
            features=object_features(pre, before.box),
            pre_place=pre_place,
            turn=None if pre_place is None else perceived_turn(pre, pre_place, post),
        )

    def ground_operation(self, pre: np.ndarray, post: np.ndarray) -> Grounding:
        """The operation's grounding from its pre- and post-action observations: the one
        object that moved (:func:`~vslsp.grounding.operation.ground`)."""
        return ground(pre, post, self.robot_side)

    def demonstration(self, operations: tuple[Operation, ...]) -> Demonstration:
        return Demonstration(self.landmark, operations, self.robot_side)


def perceived_turn(
    pre: np.ndarray, pre_place: np.ndarray, post: np.ndarray, parameters: ObjectFinding = DEFAULT_OBJECT_FINDING
) -> float:
    """How far (rad) the tutor turned the moved object: its pixels are where the pre-pick and
    the post-place observations (H, W, 3) differ from the pre-place one (image subtraction),
    and the turn is the rotation that best lays the first patch onto the second (a window
    search over the angle, 3° steps refined to 0.05°, in a window of ``parameters.patch`` px)."""
    side = parameters.patch
    before, before_mask = _object_patch(pre, pre_place, side)
    after, after_mask = _object_patch(post, pre_place, side)

    def mismatch(angle: float) -> float:
        turn = cv2.getRotationMatrix2D((side / 2.0, side / 2.0), -np.degrees(angle), 1.0)
        grey = cv2.warpAffine(before, turn, (side, side), flags=cv2.INTER_LINEAR)
        mask = cv2.warpAffine(before_mask, turn, (side, side), flags=cv2.INTER_LINEAR)
        union = cv2.max(mask, after_mask)
        return float(cv2.absdiff(grey, after).ravel() @ union.ravel() / max(float(union.sum()), 1.0))

    angle = 0.0
    for step, reach in ((3.0, 180.0), (0.25, 3.0), (0.05, 0.25)):  # coarse to fine window search
        angles = angle + np.radians(np.arange(-reach, reach, step))
        angle = float(angles[int(np.argmin([mismatch(a) for a in angles]))])
    return wrap(angle)


def _object_patch(image: np.ndarray, without: np.ndarray, side: int) -> tuple[np.ndarray, np.ndarray]:
    """The object that ``image`` has and ``without`` lacks: a grey window (P, P) (P: ``side``) float32 of
    ``image`` centred on the changed pixels' centroid, masked by them (P, P) float32."""
    changed = changed_pixels(image, without, opening=np.ones((3, 3), np.uint8))
    ys, xs = np.nonzero(changed)
    if len(xs) < 50:
        raise InputError(
            "the moved object is not seen in the demonstration's observations; "
            "keep it in view and let it differ from the board"
        )
    shift = np.array([[1.0, 0.0, side / 2.0 - xs.mean()], [0.0, 1.0, side / 2.0 - ys.mean()]])
    grey = cv2.cvtColor(image, cv2.COLOR_RGB2GRAY).astype(np.float32)
    patch = cv2.warpAffine(grey, shift, (side, side), flags=cv2.INTER_LINEAR)
    mask = cv2.warpAffine(changed.astype(np.float32), shift, (side, side), flags=cv2.INTER_LINEAR)
    return patch * mask, mask
