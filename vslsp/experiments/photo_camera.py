"""A user's camera over a table, simulated with OpenCV's camera model: a flat picture of the
table top (a :class:`TablePicture`, composed top-down in table metres) photographed through a
pinhole K, a pose (the table frame in the camera frame: a table point X is seen at
K (R X + t)), lens distortion (k1, k2, p1, p2, k3, as ``cv2.projectPoints`` applies it),
defocus and motion blur, sensor noise and JPEG compression. No part of vslsp renders these
pictures, so they test VSL on pictures as a user's camera takes them (docs/recordings.md).
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np


@dataclass(frozen=True)
class TablePicture:
    """The table top seen straight from above: ``image`` (h, w, 3) uint8 RGB whose pixel (col,
    row) shows the table point x = x0 + col / px_per_m, y = y0 + row / px_per_m (m, z = 0)."""

    image: np.ndarray
    origin: tuple[float, float]
    px_per_m: float


@dataclass(frozen=True)
class Look:
    """What the camera adds to a picture: defocus (Gaussian sigma, px), motion blur (a line of
    ``motion_px`` px at ``motion_angle_deg``), sensor noise (Gaussian sigma, grey levels) and
    JPEG ``quality`` (0-100; None: no compression)."""

    defocus_px: float = 0.8
    motion_px: float = 2.0
    motion_angle_deg: float = 0.0
    noise: float = 2.5
    quality: int | None = 88


@dataclass(frozen=True, eq=False)
class UserCamera:
    """OpenCV's camera: ``matrix`` K (3, 3), ``distortion`` (5,), the table frame's pose in the
    camera frame ``rotation`` R (3, 3) and ``translation`` t (3,), pictures of ``size`` (W, H)."""

    matrix: np.ndarray
    distortion: np.ndarray
    rotation: np.ndarray
    translation: np.ndarray
    size: tuple[int, int]

    @classmethod
    def looking_at(
        cls,
        centre: tuple[float, float],
        distance: float,
        tilt_deg: float,
        heading_deg: float,
        focal_px: float,
        size: tuple[int, int],
        distortion: tuple[float, ...] = (0.0, 0.0, 0.0, 0.0, 0.0),
        principal_offset: tuple[float, float] = (0.0, 0.0),
    ) -> UserCamera:
        """A camera ``distance`` m from the table point ``centre`` looking at it, its axis
        ``tilt_deg`` off the vertical toward ``heading_deg`` (the table's x axis: 0); the picture's
        rows run along the table's x (its top the far side)."""
        tilt, heading = np.radians(tilt_deg), np.radians(heading_deg)
        target = np.array([centre[0], centre[1], 0.0])
        eye = target + distance * np.array(
            [-np.sin(tilt) * np.cos(heading), -np.sin(tilt) * np.sin(heading), np.cos(tilt)]
        )
        forward = (target - eye) / np.linalg.norm(target - eye)
        up_in_picture = np.array([1.0, 0.0, 0.0])  # the table's +x toward the picture's top
        right = np.cross(forward, up_in_picture)
        right /= np.linalg.norm(right)
        down = np.cross(forward, right)
        rotation = np.vstack([right, down, forward])
        width, height = size
        matrix = np.array(
            [
                [focal_px, 0.0, width / 2.0 + principal_offset[0]],
                [0.0, focal_px, height / 2.0 + principal_offset[1]],
                [0.0, 0.0, 1.0],
            ]
        )
        return cls(matrix, np.asarray(distortion, np.float64), rotation, -rotation @ eye, size)

    def calibration(self) -> dict:
        """The camera as ``calibration.json`` says it (docs/recordings.md)."""
        return {
            "camera_matrix": self.matrix.tolist(),
            "distortion": self.distortion.tolist(),
            "rvec": cv2.Rodrigues(self.rotation)[0].reshape(3).tolist(),
            "translation": self.translation.tolist(),
            "image_size": list(self.size),
        }

    def project(self, points: np.ndarray) -> np.ndarray:
        """Where the picture sees the table points (N, 3) m: (N, 2) px, distortion included."""
        rvec = cv2.Rodrigues(self.rotation)[0]
        seen, _ = cv2.projectPoints(
            np.asarray(points, np.float64).reshape(-1, 1, 3), rvec, self.translation, self.matrix, self.distortion
        )
        return seen.reshape(-1, 2)

    def table_maps(self, table: TablePicture) -> tuple[np.ndarray, np.ndarray]:
        """For every pixel of the picture (H, W), the ``table`` picture's pixel it sees (cols, rows)."""
        width, height = self.size
        grid = np.stack(np.meshgrid(np.arange(width), np.arange(height)), axis=-1).reshape(-1, 1, 2)
        ideal = cv2.undistortPoints(grid.astype(np.float64), self.matrix, self.distortion, P=self.matrix)
        # the undistorted pixel -> the table plane z = 0: the inverse of K [r1 r2 t]
        plane = self.matrix @ np.column_stack([self.rotation[:, 0], self.rotation[:, 1], self.translation])
        seen = cv2.perspectiveTransform(ideal, np.linalg.inv(plane)).reshape(height, width, 2)
        cols = (seen[..., 0] - table.origin[0]) * table.px_per_m
        rows = (seen[..., 1] - table.origin[1]) * table.px_per_m
        return cols.astype(np.float32), rows.astype(np.float32)

    def photograph(self, table: TablePicture, look: Look, rng: np.random.Generator) -> np.ndarray:
        """The picture (H, W, 3) uint8 RGB of the ``table`` through this camera, with ``look``."""
        cols, rows = self.table_maps(table)
        # the table picture is finer than the camera's pixels: smooth it to their footprint first
        footprint = float(np.median(np.abs(np.diff(cols, axis=1))))  # table pixels a camera pixel
        source = table.image
        if footprint > 1.2:
            source = cv2.GaussianBlur(source, (0, 0), 0.45 * footprint)
        picture = cv2.remap(source, cols, rows, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REFLECT)
        return apply_look(picture, look, rng)


def apply_look(picture: np.ndarray, look: Look, rng: np.random.Generator) -> np.ndarray:
    """``picture`` (H, W, 3) uint8 as the camera's optics and sensor spoil it (``look``)."""
    image = picture.astype(np.float32)
    if look.defocus_px > 0:
        image = cv2.GaussianBlur(image, (0, 0), look.defocus_px)
    if look.motion_px >= 1:
        length = int(np.ceil(look.motion_px)) | 1
        kernel = np.zeros((length, length), np.float32)
        kernel[length // 2, :] = 1.0
        turn = cv2.getRotationMatrix2D((length / 2 - 0.5, length / 2 - 0.5), look.motion_angle_deg, 1.0)
        kernel = cv2.warpAffine(kernel, turn, (length, length))
        image = cv2.filter2D(image, -1, kernel / max(kernel.sum(), 1e-6))
    if look.noise > 0:
        image = image + rng.normal(0.0, look.noise, image.shape).astype(np.float32)
    image = np.clip(np.rint(image), 0, 255).astype(np.uint8)
    if look.quality is not None:
        ok, data = cv2.imencode(
            ".jpg", cv2.cvtColor(image, cv2.COLOR_RGB2BGR), [cv2.IMWRITE_JPEG_QUALITY, look.quality]
        )
        assert ok
        image = cv2.cvtColor(cv2.imdecode(data, cv2.IMREAD_COLOR), cv2.COLOR_BGR2RGB)
    return image


def checkerboard(pattern: tuple[int, int], square_m: float, px_per_m: float, margin_m: float = 0.03) -> TablePicture:
    """A printed checkerboard of ``pattern`` (cols, rows) inner corners and ``square_m`` squares
    on white paper, its first inner corner at the table's origin, the corner of column i and
    row j at table (i s, -j s) (the table frame of :mod:`vslsp.vsl.calibrate`)."""
    cols, rows = pattern
    side = int(round(square_m * px_per_m))
    margin = int(round(margin_m * px_per_m))
    board = np.full(((rows + 1) * side + 2 * margin, (cols + 1) * side + 2 * margin, 3), 255, np.uint8)
    for i in range(cols + 1):
        for j in range(rows + 1):
            if (i + j) % 2 == 0:
                board[margin + j * side : margin + (j + 1) * side, margin + i * side : margin + (i + 1) * side] = 20
    board = board[::-1]  # table rows run with +y; the board's rows with -y
    # the first inner corner lies between pixels top - 1 and top (before the flip; pixels are
    # sampled at their centres), between rows H - top - 1 and H - top after it
    top = margin + side
    x0, y0 = -(top - 0.5) / px_per_m, -(board.shape[0] - top - 0.5) / px_per_m
    return TablePicture(board, (x0, y0), px_per_m)
