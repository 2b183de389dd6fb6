"""A VSL-3D demonstration recorded as a folder of point clouds or depth images
(docs/recordings.md, "VSL-3D"): per operation the pre- and post-action worlds of Algorithm 1
part I (paper, section "VSL-3D") as numbered files, read and checked before any work, then
learned by :func:`~vslsp.vsl3d.vsl.get_object`, the table-cleaning experiment's getObject.

Per operation i (1, 2, ... without gaps): ``i-pre`` and ``i-post`` as a cloud (``.ply``,
``.pcd``, ``.npz``: points in the camera frame, metres) or a depth image (``-depth.png``,
16-bit, millimetres); ``i-pre`` may be left out for i > 1 (the world as the last operation left
it). ``calibration.json`` is required: the camera matrix K and the image size (W, H), and the
table frame's pose in the camera frame (``rotation`` R or ``rvec``, ``translation`` t: a table
point X is at R X + t in the camera frame), so that VSL-3D works in the table frame (z up from
the table top), where objects turn about the vertical. Optional: ``workspace`` (``lower``,
``upper``: the cuboid of the table frame that holds the objects; the default starts just above
the table top), ``depth_scale_m`` (a depth PNG's unit, default 0.001) and ``names.json``.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from vslsp.errors import GroundingFailed, InputError, TaskFailed
from vslsp.files import shown
from vslsp.folders import Form, operation_files, read_names, read_parsed
from vslsp.vsl3d.cloud import DepthCamera, Frame
from vslsp.vsl3d.files import CLOUD_EXTENSIONS, MAX_CLOUD_BYTES, depth_from_cloud, read_cloud, read_depth_png
from vslsp.vsl3d.vsl import MIN_CLUSTER_POINTS, MovedObject, WorldCloud, get_object

ROLES = ("pre", "post")
# Just above the table top (the pass-through drops the table itself) to 40 cm over it.
DEFAULT_WORKSPACE = Frame((-5.0, -5.0, 0.006), (5.0, 5.0, 0.40))
MIN_WORLD_POINTS = 200  # fewer points in the workspace: the capture shows no object
MAX_SIDE, MAX_PIXELS = 8192, 40_000_000  # a depth image's (perception's limits, vslsp.vision.image)


@dataclass(frozen=True, eq=False)
class CloudCalibration:
    """The depth sensor over the table: its :class:`DepthCamera` (intrinsics, its pose in the
    table frame, the image size), the workspace cuboid of the table frame, a depth PNG's unit
    and ``data``, the calibration as read."""

    camera: DepthCamera
    workspace: Frame
    depth_scale: float
    data: dict

    @property
    def size(self) -> tuple[int, int]:
        return self.camera.width, self.camera.height

    def to_table(self, points: np.ndarray) -> np.ndarray:
        """Camera-frame points (N, 3) in the table frame."""
        pose = self.camera.pose
        return points @ pose[:3, :3].T + pose[:3, 3]

    def to_camera(self, transform: np.ndarray) -> np.ndarray:
        """A motion (4, 4) of the table frame told in the camera frame."""
        pose = self.camera.pose
        return np.linalg.inv(pose) @ transform @ pose


def calibration_from_dict(data: object) -> CloudCalibration:
    """The calibration of parsed JSON ``data``; raises InputError (without a file name)."""
    try:
        if not isinstance(data, dict):
            raise ValueError("it is not a JSON object")
        matrix = np.asarray(data["camera_matrix"], dtype=float)
        width, height = (int(c) for c in data["image_size"])
        if "rvec" in data:
            rotation = cv2.Rodrigues(np.asarray(data["rvec"], dtype=float).reshape(3))[0]
        else:
            rotation = np.asarray(data["rotation"], dtype=float)
        translation = np.asarray(data["translation"], dtype=float).reshape(3)
        if matrix.shape != (3, 3) or rotation.shape != (3, 3) or not (width > 0 and height > 0):
            raise ValueError("camera_matrix and rotation are 3x3, image_size [W, H] positive")
        if max(width, height) > MAX_SIDE or width * height > MAX_PIXELS:  # a depth image is W x H floats
            raise ValueError(f"image_size {width}x{height} is over a camera's ({MAX_SIDE} a side, 40 megapixels)")
        if not np.allclose(rotation @ rotation.T, np.eye(3), atol=1e-4) or np.linalg.det(rotation) < 0:
            raise ValueError("rotation is not a rotation matrix")
        if not (np.all(np.isfinite(matrix)) and np.all(np.isfinite(translation))):
            raise ValueError("its numbers must be finite")
        space = data.get("workspace")
        workspace = DEFAULT_WORKSPACE if space is None else Frame.from_dict(space)
        scale = float(data.get("depth_scale_m", 0.001))
        if not scale > 0.0:
            raise ValueError("depth_scale_m must be > 0")
    except InputError as error:
        raise InputError(f"its workspace: {error}") from None
    except (ValueError, KeyError, TypeError, IndexError, AttributeError, cv2.error) as error:
        raise InputError(
            f"not a VSL-3D calibration ({error}); give camera_matrix, image_size and the table's rotation "
            "(or rvec) and translation in the camera frame (docs/recordings.md)"
        ) from None
    pose = np.eye(4)  # the camera in the table frame: the inverse of the table's pose in the camera's
    pose[:3, :3] = rotation.T
    pose[:3, 3] = -rotation.T @ translation
    return CloudCalibration(DepthCamera(matrix, pose, width, height), workspace, scale, data)


@dataclass(frozen=True, eq=False)
class CloudRecording:
    """A folder of a VSL-3D demonstration, read: per operation its pre- and post-action world
    clouds (table frame), their files, the objects' names and the calibration."""

    folder: Path
    worlds: tuple[dict[str, WorldCloud], ...]
    files: tuple[dict[str, str], ...]
    names: tuple[str, ...]
    calibration: CloudCalibration


FORM = Form(
    re.compile(r"^(\d{1,4})-(pre|post)(-depth\.png|\.ply|\.pcd|\.npz)$", re.IGNORECASE),
    (*CLOUD_EXTENSIONS, ".png"),
    {
        "post": "post-action cloud (.ply, .pcd, .npz or -depth.png)",
        "pre": "pre-action cloud (.ply, .pcd, .npz or -depth.png)",
    },
    ("pre",),
    "NN-pre or NN-post (.ply, .pcd, .npz, -depth.png)",
    "capture",
    "01-pre.ply, 01-post.ply",
    "the demonstration's clouds",
)


def read_cloud_recording(folder: str | Path, max_bytes: int = MAX_CLOUD_BYTES) -> CloudRecording:
    """Read and check the recording in ``folder`` (see the module's docstring). Raises
    InputError naming the file: a missing, unreadable or empty cloud, one of more than
    ``max_bytes``, a depth image of another size, operations out of order, a calibration or
    names file that does not parse or fit."""
    folder = Path(folder)
    found = operation_files(folder, FORM)
    path = folder / "calibration.json"
    if not path.is_file():
        raise InputError(
            f"{shown(path)} is missing: VSL-3D needs the camera matrix and the table plane (docs/recordings.md)"
        )
    calibration = read_parsed(path, "calibration", calibration_from_dict)
    worlds: list[dict[str, WorldCloud]] = []
    files: list[dict[str, str]] = []
    for number in sorted(found):
        roles = found[number]
        clouds = {role: read_world(file, calibration, max_bytes) for role, file in roles.items()}
        clouds.setdefault("pre", worlds[-1]["post"] if worlds else clouds["post"])
        worlds.append(clouds)
        files.append({role: file.name for role, file in roles.items()})
    names = read_names(folder / "names.json", len(worlds))
    return CloudRecording(folder, tuple(worlds), tuple(files), names, calibration)


def read_world(path: str | Path, calibration: CloudCalibration, max_bytes: int = MAX_CLOUD_BYTES) -> WorldCloud:
    """The world cloud of one capture file (a cloud of at most ``max_bytes``, or a depth PNG) in
    the table frame, cut to the workspace. Raises InputError naming the file when it shows
    nothing in the workspace."""
    path = Path(path)
    if path.name.lower().endswith("-depth.png"):
        depth = read_depth_png(path, calibration.depth_scale, calibration.size)
    else:
        points = read_cloud(path, max_bytes)
        depth = depth_from_cloud(points, calibration.camera.intrinsics, calibration.size)
    world = WorldCloud.capture(depth, calibration.camera, calibration.workspace)
    if len(world.points) < MIN_WORLD_POINTS:
        raise InputError(
            f"{shown(path)}: only {len(world.points)} of its points lie in the workspace above the table; "
            "check calibration.json's camera pose and workspace, or capture the scene again"
        )
    return world


def learn(recording: CloudRecording, method: str = "prerejective_ransac", seed: int = 0) -> tuple[MovedObject, ...]:
    """Algorithm 1 part I on a recording: getObject of each operation's pre- and post-action
    worlds. Raises GroundingFailed (exit 1) naming the operation whose object is not found."""
    moved = []
    for k, worlds in enumerate(recording.worlds, start=1):
        try:
            moved.append(
                get_object(worlds["pre"], worlds["post"], min_points=MIN_CLUSTER_POINTS, method=method, seed=seed)
            )
        except TaskFailed as error:
            raise GroundingFailed(f"operation {k} ({recording.names[k - 1]}): {error}") from None
    return tuple(moved)
