"""A VSL-3D demonstration learned from a folder of clouds (:mod:`vslsp.vsl3d.recordings`), on
disk and in use: ``vsl3d-demonstration.json`` (per operation the object's name, its motion T_j
(4, 4), the frames and centroids; the calibration) and ``observations.npz`` (each operation's
pre- and post-action observations' points and viewpoints; no pickle).

:func:`next_operation` is Algorithm 1 part II, lines 13-15, for one operation in a user's
capture of the new scene, as the table-cleaning experiment reproduces
(:mod:`vslsp.experiments.cloud_reproduction`): findBestMatch finds the recorded pre-action
observation (M_j) in the world less what earlier operations put down, the grasp comes from the
matched cloud, and the object goes to T_j M_j^-1; told in the table frame and the camera's.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from vslsp.errors import InputError, TaskFailed
from vslsp.files import load_npz
from vslsp.folders import read_record, unreadable, write_learned
from vslsp.outcomes import NoMatch
from vslsp.vsl3d.cloud import Frame
from vslsp.vsl3d.grasping import place_for, plan_grasp
from vslsp.vsl3d.matching import find_best_match
from vslsp.vsl3d.recordings import CloudCalibration, CloudRecording, calibration_from_dict
from vslsp.vsl3d.registration import transform_error, transform_points
from vslsp.vsl3d.vsl import CloudObservation, MovedObject, WorldCloud

FORMAT = "vslsp-vsl3d-files/1"
RECORD = "vsl3d-demonstration.json"
OBSERVATIONS = "observations.npz"
MAX_RECORD_BYTES = 10_000_000
MAX_OBSERVATION_BYTES = 512_000_000
FINGER_OPEN = 0.04  # m each finger opens from the gripper's middle (a Franka hand's 8 cm)


@dataclass(frozen=True, eq=False)
class LearnedClouds:
    """A learned VSL-3D demonstration: per operation the object's pre-action observation and
    its motion T_j (4, 4); the objects' names, the calibration, getObject's method and seed."""

    observations: tuple[CloudObservation, ...]
    motions: tuple[np.ndarray, ...]
    names: tuple[str, ...]
    calibration: CloudCalibration
    method: str
    seed: int

    def __len__(self) -> int:
        return len(self.observations)


def save_learned(
    moved: tuple[MovedObject, ...], recording: CloudRecording, folder: str | Path, method: str, seed: int
) -> Path:
    """Write the objects ``moved`` learned from ``recording`` into ``folder`` (it exists); the
    record's path."""
    folder = Path(folder)
    arrays: dict[str, np.ndarray] = {}
    records = []
    for i, obj in enumerate(moved, start=1):
        for side, observation in (("pre", obj.pre), ("post", obj.post)):
            arrays[f"op{i:02d}_{side}_points"] = observation.points
            arrays[f"op{i:02d}_{side}_viewpoint"] = np.asarray(observation.viewpoint, dtype=float)
        records.append({"name": recording.names[i - 1], "clouds": recording.files[i - 1], **obj.to_dict()})
    record = {
        "format": FORMAT,
        "recording": os.path.abspath(recording.folder),
        "method": method,
        "seed": seed,
        "calibration": recording.calibration.data,
        "operations": records,
    }
    return write_learned(folder, RECORD, record, OBSERVATIONS, arrays, compressed=True)


def load_learned(folder: str | Path) -> LearnedClouds:
    """Read a demonstration written by :func:`save_learned`; InputError naming the file when
    ``folder`` is not one."""
    folder = Path(folder)
    path, data = read_record(
        folder, RECORD, FORMAT, "learned VSL-3D demonstration", "vslsp vsl3d learn", MAX_RECORD_BYTES
    )
    try:
        arrays = load_npz(folder / OBSERVATIONS, "demonstration's observations", MAX_OBSERVATION_BYTES)
        observations, motions = [], []
        for i, op in enumerate(data["operations"], start=1):
            points = np.asarray(arrays[f"op{i:02d}_pre_points"], dtype=float)
            viewpoint = np.asarray(arrays[f"op{i:02d}_pre_viewpoint"], dtype=float)
            observations.append(CloudObservation(points, Frame.from_dict(op["pre"]["frame"]), viewpoint))
            motion = np.asarray(op["transform"], dtype=float)
            if motion.shape != (4, 4) or points.ndim != 2 or points.shape[1] != 3:
                raise ValueError(f"operation {i}'s observation or motion has the wrong shape")
            motions.append(motion)
        if not observations:
            raise ValueError("it has no operations")
        names = tuple(str(op["name"]) for op in data["operations"])
        calibration = calibration_from_dict(data["calibration"])
        method, seed = str(data["method"]), int(data["seed"])
    except (ValueError, KeyError, TypeError, IndexError, AttributeError, InputError) as error:
        raise unreadable(path, error, "vslsp vsl3d learn") from None
    return LearnedClouds(tuple(observations), tuple(motions), names, calibration, method, seed)


def next_operation(learned: LearnedClouds, k: int, world: WorldCloud, finger_open: float = FINGER_OPEN) -> dict:
    """Where to pick and place operation ``k``'s (0-based) object in ``world``, the user's
    capture of the new scene: the object found (its centroid and its pose M_j, the recorded
    pre-action observation moved onto it), the grasp, and where it goes (its centroid and pose
    T_j afterwards, the fingertips' place point and the hand's angle; the motion T_j M_j^-1),
    in the table frame and (``camera``) in the camera frame. Raises TaskFailed (exit 1) when
    the object is not found."""
    calibration = learned.calibration
    placed = [transform_points(learned.motions[i], learned.observations[i].points) for i in range(k)]
    search = world.without(np.vstack(placed)) if placed else world  # what earlier operations put down
    observation, goal = learned.observations[k], learned.motions[k]
    match = find_best_match(search, observation, method=learned.method, seed=learned.seed)
    if isinstance(match, NoMatch):
        raise TaskFailed(f"operation {k + 1} ({learned.names[k]}): {match.reason}", cause="no match")
    pose = match.registration.transform
    motion = goal @ np.linalg.inv(pose)  # T_j M_j^-1
    grasp = plan_grasp(match.points, finger_open)
    place_point, place_angle = place_for(grasp, motion)
    centre = match.position
    goal_centre = transform_points(motion, centre[None])[0]
    _, turn = transform_error(motion, np.eye(4), centre)
    return {
        "done": False,
        "operation": k + 1,
        "operations": len(learned),
        "name": learned.names[k],
        "pick": {
            **_where(calibration, centre, pose),
            "grasp": {
                "point_m": _rounded(grasp.point),
                "hand_angle_rad": round(grasp.theta, 4),
                "width_m": round(grasp.width, 4),
                "top_m": round(grasp.top, 4),
            },
        },
        "place": {
            **_where(calibration, goal_centre, goal),
            "grasp": {"point_m": _rounded(place_point), "hand_angle_rad": round(place_angle, 4)},
        },
        "motion": _rounded(motion),
        "motion_camera": _rounded(calibration.to_camera(motion)),
        "rotation_deg": round(turn, 2),
        "match": {
            "fitness": round(match.registration.fitness, 4),
            "rmse_m": round(match.registration.rmse, 5),
            "method": match.registration.method,
        },
    }


def _where(calibration: CloudCalibration, centre: np.ndarray, pose: np.ndarray) -> dict:
    """The object's centroid (3,) and pose (4, 4: from the recorded pre-action observation),
    in the table frame and the camera frame."""
    to_camera = np.linalg.inv(calibration.camera.pose)
    return {
        "centroid_m": _rounded(centre),
        "pose": _rounded(pose),
        "centroid_camera_m": _rounded(transform_points(to_camera, centre[None])[0]),
        "pose_camera": _rounded(calibration.to_camera(pose)),
    }


def _rounded(values: np.ndarray) -> list:
    return np.round(np.asarray(values, dtype=float), 5).tolist()
