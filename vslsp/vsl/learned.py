"""A demonstration learned from a folder of pictures (:mod:`vslsp.vsl.recordings`), on disk
and in use: ``vsl-demonstration.json`` (the operations: points, footprints, yaws, turns,
heights; the calibration and the objects' names), ``features.npz`` (each object's SIFT
keypoints and descriptors φ, read with ``allow_pickle=False``) and the recorded observations
seen from above (``NN-pre-pick.png``, ``NN-pre-place.png``, ``NN-post-place.png``). No pickle.

:func:`next_operation` is Algorithm 1 part II, lines 13-15, for one operation in a user's
picture of the new scene: the pick and place matched by
:func:`~vslsp.vsl.reproduction.plan_operation` (the Panda's tasks' reproduction), told in the
picture's pixels and, with a calibration, in table metres. A :class:`Session` keeps which
operation is next between the user's robot's moves (docs/recordings.md).
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from vslsp.errors import InputError, TaskFailed
from vslsp.files import load_npz, read_json, shown
from vslsp.folders import read_record, unreadable, write_learned
from vslsp.geometry.poses import wrap
from vslsp.outputs import write_text
from vslsp.vision.features import Features
from vslsp.vision.image import read_image, write_image
from vslsp.vision.matching import NoMatch
from vslsp.vsl.calibration import Calibration, calibration_from_dict, uncalibrated
from vslsp.vsl.pick_place import PickPlaceDemonstration, RecordedOperation, apply
from vslsp.vsl.recordings import Recording
from vslsp.vsl.reproduction import plan_operation

FORMAT = "vslsp-vsl-files/1"
SESSION_FORMAT = "vslsp-vsl-session/1"
RECORD = "vsl-demonstration.json"
FEATURES = "features.npz"
MAX_RECORD_BYTES = 10_000_000
MAX_FEATURE_BYTES = 512_000_000
OBSERVATIONS = ("pre_pick", "pre_place", "post_place")
_SCALARS = ("yaw", "turn", "object_size", "pick_z", "place_z")


@dataclass(frozen=True, eq=False)
class Learned:
    """A learned demonstration: the operations, the camera, the objects' names, the pictures'
    size (W, H) px."""

    demonstration: PickPlaceDemonstration
    calibration: Calibration
    names: tuple[str, ...]
    size: tuple[int, int]

    def __len__(self) -> int:
        return len(self.demonstration.operations)


def save_learned(demo: PickPlaceDemonstration, recording: Recording, folder: str | Path) -> Path:
    """Write ``demo``, learned from ``recording``, into ``folder`` (it exists); returns the
    record's path."""
    folder = Path(folder)
    arrays: dict[str, np.ndarray] = {}
    records = []
    for i, op in enumerate(demo.operations, start=1):
        files = {}
        for which in OBSERVATIONS:
            files[which] = f"{i:02d}-{which.replace('_', '-')}.png"
            write_image(folder / files[which], getattr(op, which))
        arrays.update(op.features.to_arrays(f"op{i:02d}"))
        records.append(
            {
                "name": recording.names[i - 1],
                "pictures": recording.files[i - 1],
                "observations": files,
                "pick_point": list(op.pick_point),
                "place_point": list(op.place_point),
                "footprint": list(op.footprint),
                **{key: getattr(op, key) for key in _SCALARS},
                "features": len(op.features),
            }
        )
    record = {
        "format": FORMAT,
        "recording": os.path.abspath(recording.folder),
        "image_size": list(recording.size),
        "calibration": recording.calibration.data,
        "operations": records,
    }
    return write_learned(folder, RECORD, record, FEATURES, arrays)


def load_learned(folder: str | Path) -> Learned:
    """Read a demonstration written by :func:`save_learned`. Raises InputError naming the
    file when ``folder`` is not one."""
    folder = Path(folder)
    path, data = read_record(folder, RECORD, FORMAT, "learned demonstration", "vslsp vsl learn", MAX_RECORD_BYTES)
    try:
        size = (int(data["image_size"][0]), int(data["image_size"][1]))
        arrays = load_npz(folder / FEATURES, "demonstration's features", MAX_FEATURE_BYTES)
        operations = []
        for i, op in enumerate(data["operations"], start=1):
            images = {which: read_image(folder / op["observations"][which]) for which in OBSERVATIONS}
            operations.append(
                RecordedOperation(
                    images["pre_pick"],
                    images["pre_place"],
                    images["post_place"],
                    _pair(op["pick_point"]),
                    _pair(op["place_point"]),
                    _pair(op["footprint"]),
                    float(op["yaw"]),
                    float(op["turn"]),
                    float(op["object_size"]),
                    float(op["pick_z"]),
                    float(op["place_z"]),
                    Features.from_arrays(arrays, f"op{i:02d}"),
                )
            )
        if not operations:
            raise ValueError("it has no operations")
        names = tuple(str(op["name"]) for op in data["operations"])
        calibration = (
            uncalibrated(size) if data["calibration"] is None else calibration_from_dict(data["calibration"], size)
        )
    except (ValueError, KeyError, TypeError, IndexError, AttributeError) as error:
        raise unreadable(path, error, "vslsp vsl learn") from None
    return Learned(PickPlaceDemonstration(tuple(operations)), calibration, names, size)


def _pair(value) -> tuple[float, float]:
    first, second = value
    return float(first), float(second)


def next_operation(learned: Learned, k: int, scene: np.ndarray) -> dict:
    """Where to pick and place for operation ``k`` (0-based) in the user's picture ``scene``
    (H, W, 3) of the new world: a dict of the operation, the object's name, the pick and the
    place (``pixel``: the object's centre in ``scene`` at its top; with a calibration ``table_m``
    (x, y) and the hand's closing-axis angle ``hand_angle_rad``), the turn and, with a
    calibration, the grasp width; the matches. Raises TaskFailed (exit 1) when the recorded
    object or place is not found in the scene."""
    demo, calibration = learned.demonstration, learned.calibration
    op = demo.operations[k]
    seen = calibration.observe(scene)
    planned = plan_operation(demo, k, seen, calibration.view)
    if isinstance(planned, NoMatch):
        raise TaskFailed(f"operation {k + 1} ({learned.names[k]}): {planned.reason}", cause="no match")
    answer: dict = {"done": False, "operation": k + 1, "operations": len(learned), "name": learned.names[k]}
    for role, pose, z, match, point in (
        ("pick", planned.pick, op.pick_z, planned.pick_match, op.pick_point),
        ("place", planned.place, op.place_z, planned.place_match, op.place_point),
    ):
        x, y = calibration.view.pixel_to_table(*apply(match.transform, point), z)
        u, v = calibration.image_pixel(x, y, z)
        where: dict = {"pixel": [round(u, 1), round(v, 1)]}
        if calibration.calibrated:
            where |= {
                "table_m": [round(pose[0], 4), round(pose[1], 4)],
                "hand_angle_rad": round(pose[2], 4),
                "z_m": round(z, 4),
            }
        answer[role] = where
    answer["turn_rad"] = round(wrap(planned.place[2] - planned.pick[2]), 4)
    if calibration.calibrated:
        answer["grasp_width_m"] = round(planned.grasp_width, 4)
    matches = planned.to_dict()
    answer["matches"] = {"pick": matches["pick_match"], "place": matches["place_match"]}
    return answer


@dataclass
class Session:
    """Which operation of a learned demonstration is next (0-based) and the answers given."""

    demonstration: str
    next: int = 0
    given: list | None = None

    @classmethod
    def open(cls, path: str | Path, demonstration: str | Path, operations: int) -> Session:
        """The session in ``path`` (a new one when the file does not exist). Raises InputError
        naming the file when it is not a session of ``demonstration``."""
        path, where = Path(path), os.path.abspath(demonstration)
        if not path.exists():
            return cls(where, 0, [])
        data = read_json(path, "session", MAX_RECORD_BYTES)
        try:
            if data["format"] != SESSION_FORMAT:
                raise ValueError
            session = cls(str(data["demonstration"]), int(data["next"]), list(data["given"]))
        except (ValueError, KeyError, TypeError):
            raise InputError(
                f"{shown(path)} is not a vslsp session file; give a new file name to start a session"
            ) from None
        if session.demonstration != where:
            raise InputError(
                f"{shown(path)} is the session of {session.demonstration}, not of {where}; "
                "give another session file to start anew"
            )
        if not 0 <= session.next <= operations:
            raise InputError(f"{shown(path)}: its next operation {session.next + 1} is not in the demonstration")
        return session

    def save(self, path: str | Path) -> None:
        record = {"format": SESSION_FORMAT, "demonstration": self.demonstration, "next": self.next, "given": self.given}
        write_text(path, json.dumps(record, indent=2) + "\n")
