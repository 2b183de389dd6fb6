"""A user's camera over a table, read from ``calibration.json`` (docs/recordings.md): the
:class:`~vslsp.vsl.pick_place.TableCamera` that VSL's table model
(:class:`~vslsp.vsl.pick_place.TableModel`) unprojects the tutor's objects with, and the
top-down :class:`~vslsp.vsl.pick_place.TableView` it sees them in.

Two calibrations: OpenCV's pinhole camera (``camera_matrix`` K, ``distortion``, and the table
plane as the table frame's pose in the camera frame, ``rotation`` R or ``rvec`` and
``translation`` t: a table point X is seen at K (R X + t)), or a ``homography`` (3, 3) from
image pixels to table metres (the plane of the table top; heights above it are not told
apart). Without a calibration the images are taken as seen straight from above, one pixel a
millimetre (:func:`uncalibrated`): the answers are then pixels only.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import cv2
import numpy as np

from vslsp.errors import InputError
from vslsp.folders import read_parsed
from vslsp.vision.image import flatten_table
from vslsp.vsl.pick_place import TableCamera, TableView

NOMINAL_PX_PER_M = 1000.0  # an uncalibrated image: one pixel a millimetre


@dataclass(frozen=True, eq=False)
class PinholeTable:
    """A pinhole camera K (3, 3) over the table plane: a table point X (m, z up from the table
    top) is seen at K (R X + t), R (3, 3) and t (3,) the table frame's pose in the camera frame."""

    matrix: np.ndarray
    rotation: np.ndarray
    translation: np.ndarray

    def table_to_pixel(self, x: float, y: float, z: float = 0.0) -> tuple[float, float]:
        seen = self.matrix @ (self.rotation @ np.array([x, y, z]) + self.translation)
        return float(seen[0] / seen[2]), float(seen[1] / seen[2])

    def pixel_to_table(self, u: float, v: float, z: float = 0.0) -> tuple[float, float]:
        """The point (x, y) of the plane at height ``z`` seen at pixel (u, v)."""
        eye = -self.rotation.T @ self.translation
        ray = self.rotation.T @ np.linalg.solve(self.matrix, np.array([u, v, 1.0]))
        if abs(ray[2]) < 1e-12 or (z - eye[2]) / ray[2] <= 0:
            raise ValueError(f"pixel ({u}, {v}) does not see the table plane")
        point = eye + ray * (z - eye[2]) / ray[2]
        return float(point[0]), float(point[1])


@dataclass(frozen=True, eq=False)
class PlaneHomography:
    """A homography (3, 3) from image pixels to table metres; every height is the table's."""

    homography: np.ndarray

    def pixel_to_table(self, u: float, v: float, z: float = 0.0) -> tuple[float, float]:
        x, y, w = self.homography @ np.array([u, v, 1.0])
        return float(x / w), float(y / w)

    def table_to_pixel(self, x: float, y: float, z: float = 0.0) -> tuple[float, float]:
        u, v, w = np.linalg.solve(self.homography, np.array([x, y, 1.0]))
        return float(u / w), float(v / w)


@dataclass(frozen=True, eq=False)
class Calibration:
    """The camera of a recording: its :class:`TableCamera` (undistorted pixels), the lens
    distortion (OpenCV's coefficients, or None), the top-down view VSL sees the table in,
    and ``data``, the calibration as read (None: uncalibrated)."""

    camera: TableCamera
    view: TableView
    distortion: np.ndarray | None
    data: dict | None

    @property
    def calibrated(self) -> bool:
        return self.data is not None

    def undistort(self, image: np.ndarray) -> np.ndarray:
        """The image (H, W, 3) as a lens without distortion would have seen it."""
        if self.distortion is None or not isinstance(self.camera, PinholeTable):
            return image
        return cv2.undistort(image, self.camera.matrix, self.distortion)

    def observe(self, image: np.ndarray) -> np.ndarray:
        """What VSL sees of a user's image (H, W, 3): undistorted, seen from above (h, w, 3),
        the table top one flat colour (:func:`~vslsp.vision.image.flatten_table`)."""
        return flatten_table(self.view.rectify(self.undistort(image)))

    def undistort_point(self, u: float, v: float) -> tuple[float, float]:
        """The pixel of the undistorted image (:meth:`undistort`) that shows what the user's
        image shows at (u, v)."""
        if self.distortion is None or not isinstance(self.camera, PinholeTable):
            return u, v
        matrix = self.camera.matrix
        ideal = cv2.undistortPoints(np.array([[[u, v]]], np.float64), matrix, self.distortion, P=matrix)
        x, y = ideal.reshape(2)
        return float(x), float(y)

    def image_pixel(self, x: float, y: float, z: float = 0.0) -> tuple[float, float]:
        """Where the user's (distorted) image sees the table point (x, y) at height ``z`` (m)."""
        if self.distortion is None or not isinstance(self.camera, PinholeTable):
            return self.camera.table_to_pixel(x, y, z)
        camera = self.camera
        rvec = cv2.Rodrigues(camera.rotation)[0]
        seen = cv2.projectPoints(
            np.array([[x, y, z]], np.float64), rvec, camera.translation, camera.matrix, self.distortion
        )
        u, v = seen[0].reshape(2)
        return float(u), float(v)


def uncalibrated(size: tuple[int, int]) -> Calibration:
    """Images of ``size`` (W, H) px seen straight from above: x up the image, y to its left,
    :data:`NOMINAL_PX_PER_M` (the view is the image itself)."""
    width, height = size
    s = NOMINAL_PX_PER_M
    homography = np.array([[0.0, -1.0 / s, width / 2.0 / s], [-1.0 / s, 0.0, height / s], [0.0, 0.0, 1.0]])
    camera = PlaneHomography(homography)
    view = TableView(camera, (0.0, height / s), (-width / 2.0 / s, width / 2.0 / s), s, 0.0)
    return Calibration(camera, view, None, None)


def read_calibration(path: str | Path, size: tuple[int, int]) -> Calibration:
    """The calibration in ``path`` (JSON) for images of ``size`` (W, H) px. Raises InputError,
    naming the file, when it does not parse or does not fit the images."""
    return read_parsed(Path(path), "calibration", lambda data: calibration_from_dict(data, size))


def calibration_from_dict(data: Any, size: tuple[int, int]) -> Calibration:
    """:func:`read_calibration` of parsed JSON ``data`` (messages without the file's name)."""
    if not isinstance(data, dict):
        raise InputError("a calibration is a JSON object; see docs/recordings.md")
    distortion = None
    camera: TableCamera
    if "homography" in data:
        homography = _matrix(data, "homography", (3, 3))
        if abs(np.linalg.det(homography)) < 1e-15:
            raise InputError("the homography is singular; measure four table points again")
        camera = PlaneHomography(homography)
    elif "camera_matrix" in data:
        matrix = _matrix(data, "camera_matrix", (3, 3))
        if matrix[0, 0] <= 0 or matrix[1, 1] <= 0 or not np.allclose(matrix[2], [0.0, 0.0, 1.0]):
            raise InputError("camera_matrix is not OpenCV's [[fx, 0, cx], [0, fy, cy], [0, 0, 1]] with fx, fy > 0")
        if "rvec" in data:
            rotation = cv2.Rodrigues(_matrix(data, "rvec", (3,)))[0]
        else:
            rotation = _matrix(data, "rotation", (3, 3))
        if not np.allclose(rotation @ rotation.T, np.eye(3), atol=1e-4) or np.linalg.det(rotation) < 0:
            raise InputError("rotation is not a rotation matrix (orthonormal, determinant 1)")
        camera = PinholeTable(matrix, rotation, _matrix(data, "translation", (3,)))
        if "distortion" in data:
            distortion = np.asarray(data["distortion"], np.float64).ravel()
            if distortion.size not in (4, 5, 8, 12, 14) or not np.all(np.isfinite(distortion)):
                raise InputError("distortion holds 4, 5, 8, 12 or 14 of OpenCV's coefficients")
    else:
        raise InputError('give "camera_matrix" with the table plane or a "homography"; see docs/recordings.md')
    if "image_size" in data and list(data["image_size"]) != list(size):
        raise InputError(f"it is for images of {data['image_size']} px, the recording's are {list(size)}")
    view = _view(camera, data.get("workspace", {}), size)
    return Calibration(camera, view, distortion, data)


def _matrix(data: dict, key: str, shape: tuple[int, ...]) -> np.ndarray:
    if key not in data:
        raise InputError(f'"{key}" is missing; see docs/recordings.md')
    try:
        value = np.asarray(data[key], np.float64)
    except (TypeError, ValueError):
        value = np.zeros(0)
    if value.shape != shape or not np.all(np.isfinite(value)):
        raise InputError(f'"{key}" must be {" x ".join(map(str, shape))} finite numbers')
    return value


def _view(camera: TableCamera, workspace: Any, size: tuple[int, int]) -> TableView:
    """The top-down view of the ``workspace`` (default: what the image sees of the table)."""
    if not isinstance(workspace, dict):
        raise InputError('"workspace" is an object {"x": [min, max], "y": [min, max], "px_per_m": n, "z": m}')
    width, height = size
    try:
        if "x" in workspace and "y" in workspace:
            x_range = tuple(float(c) for c in workspace["x"])
            y_range = tuple(float(c) for c in workspace["y"])
        else:
            seen = np.array([camera.pixel_to_table(u, v, 0.0) for u in (0, width) for v in (0, height)])
            x_range, y_range = (seen[:, 0].min(), seen[:, 0].max()), (seen[:, 1].min(), seen[:, 1].max())
        z = float(workspace.get("z", 0.0))
        centre = camera.table_to_pixel(sum(x_range) / 2.0, sum(y_range) / 2.0, z)
    except ValueError:
        raise InputError(
            'the image corners do not all see the table; give "workspace": {"x": [min, max], "y": [min, max]} (m)'
        ) from None
    except TypeError:
        raise InputError('"workspace" x and y are [min, max] pairs of numbers (m)') from None
    if len(x_range) != 2 or len(y_range) != 2 or not x_range[0] < x_range[1] or not y_range[0] < y_range[1]:
        raise InputError('"workspace" x and y are [min, max] pairs with min < max (m)')
    if not (0 <= centre[0] < width and 0 <= centre[1] < height):
        raise InputError("the workspace's centre is not in the image: the calibration does not fit the images")
    area = (x_range[1] - x_range[0]) * (y_range[1] - y_range[0])
    try:
        px_per_m = float(workspace["px_per_m"]) if "px_per_m" in workspace else float(np.sqrt(width * height / area))
    except (TypeError, ValueError):
        raise InputError('"workspace" px_per_m is a number (view pixels a metre)') from None
    if not 0 < px_per_m * max(x_range[1] - x_range[0], y_range[1] - y_range[0]) <= 8192:
        raise InputError('the view of the workspace would be over 8192 px a side; give a smaller "px_per_m"')
    return TableView(camera, (x_range[0], x_range[1]), (y_range[0], y_range[1]), px_per_m, z)
