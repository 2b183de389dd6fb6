"""Pinhole cameras over the table: rendering and the pixel <-> table-plane mapping.

Pixel coordinates ``(u, v)``: u to the right, v down, the centre of pixel ``[row, col]`` at
``(col + 0.5, row + 0.5)``. A pixel maps to the table plane by casting its ray from the
camera centre and intersecting it with ``z = TABLE_Z``.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Any

import numpy as np

from vslsp.sim.live import publish
from vslsp.sim.quiet import quiet
from vslsp.sim.scene import TABLE_Z

with quiet():
    import pybullet as pb

NEAR, FAR = 0.05, 3.0


@dataclass(frozen=True)
class Camera:
    """A camera looking at ``target`` from ``eye`` with vertical field of view ``fov`` (deg)."""

    name: str
    eye: tuple[float, float, float]
    target: tuple[float, float, float]
    up: tuple[float, float, float]
    width: int = 640
    height: int = 480
    fov: float = 60.0

    def axes(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Unit vectors (3,) of the camera in the world: right, down (image v), forward."""
        forward = np.subtract(self.target, self.eye).astype(float)
        forward /= np.linalg.norm(forward)
        right = np.cross(forward, self.up)
        right /= np.linalg.norm(right)
        down = np.cross(forward, right)
        return right, down, forward

    @property
    def focal(self) -> float:
        """Focal length in pixels."""
        return self.height / 2.0 / np.tan(np.radians(self.fov) / 2.0)

    def intrinsics(self) -> np.ndarray:
        """The (3, 3) intrinsic matrix K."""
        f = self.focal
        return np.array([[f, 0.0, self.width / 2.0], [0.0, f, self.height / 2.0], [0.0, 0.0, 1.0]])

    def project(self, points: np.ndarray) -> np.ndarray:
        """World points (N, 3) to pixels (N, 2)."""
        right, down, forward = self.axes()
        relative = np.atleast_2d(points) - np.asarray(self.eye)
        depth = relative @ forward
        return np.column_stack(
            [
                self.width / 2.0 + self.focal * (relative @ right) / depth,
                self.height / 2.0 + self.focal * (relative @ down) / depth,
            ]
        )

    def table_to_pixel(self, x: float, y: float, z: float = TABLE_Z) -> tuple[float, float]:
        u, v = self.project(np.array([x, y, z]))[0]
        return float(u), float(v)

    def pixel_to_table(self, u: float, v: float, z: float = TABLE_Z) -> tuple[float, float]:
        """The point (x, y) of the plane at height ``z`` seen at pixel (u, v)."""
        right, down, forward = self.axes()
        ray = forward + (u - self.width / 2.0) / self.focal * right + (v - self.height / 2.0) / self.focal * down
        eye = np.asarray(self.eye, dtype=float)
        if abs(ray[2]) < 1e-9 or (z - eye[2]) / ray[2] <= 0:
            raise ValueError(f"pixel ({u}, {v}) does not see the table plane")
        point = eye + ray * (z - eye[2]) / ray[2]
        return float(point[0]), float(point[1])

    def resized(self, width: int, height: int) -> Camera:
        return Camera(self.name, self.eye, self.target, self.up, width, height, self.fov)

    def render(self, client: int, backdrop: Backdrop | None = None) -> tuple[np.ndarray, np.ndarray]:
        """RGB (H, W, 3) uint8 and depth (H, W) float32 metres along the optical axis; where
        no body was drawn and the ray meets ``backdrop``, its colour and depth."""
        view = pb.computeViewMatrix(self.eye, self.target, self.up)
        projection = pb.computeProjectionMatrixFOV(self.fov, self.width / self.height, NEAR, FAR)
        _, _, rgba, depth_buffer, _ = pb.getCameraImage(
            self.width,
            self.height,
            view,
            projection,
            shadow=0,
            lightDirection=LIGHT_DIRECTION,
            renderer=pb.ER_TINY_RENDERER,
            flags=pb.ER_NO_SEGMENTATION_MASK,
            physicsClientId=client,
        )
        rgb, depth = self._finish(rgba, depth_buffer, backdrop)
        publish(rgb)  # the studio's live picture of a running trial (vslsp.sim.live), when asked for
        return rgb, depth

    def _finish(self, rgba: Any, depth_buffer: Any, backdrop: Backdrop | None) -> tuple[np.ndarray, np.ndarray]:
        """The RGB and depth of pybullet's buffers, the ``backdrop`` drawn where no body was."""
        buffer = np.asarray(depth_buffer, dtype=np.float64).reshape(self.height, self.width)
        depth = (FAR * NEAR / (FAR - (FAR - NEAR) * buffer)).astype(np.float32)
        if backdrop is None:
            return np.asarray(rgba, dtype=np.uint8).reshape(self.height, self.width, 4)[:, :, :3].copy(), depth
        plane_depth, seen = self._plane(backdrop)
        empty = seen & (buffer >= 1.0 - 1e-6)
        if backdrop.solid:  # the plane hides what lies behind it, as the body it stands for would
            empty |= seen & (depth > plane_depth)
        pixels = np.array(rgba, dtype=np.uint8).reshape(self.height, self.width, 4)
        colour = np.array([*backdrop.colour, 255], np.uint8).view(np.uint32)[0]
        np.copyto(pixels.view(np.uint32)[:, :, 0], colour, where=empty)  # one word per pixel: quicker
        np.copyto(depth, plane_depth, where=empty)
        return pixels[:, :, :3].copy(), depth

    @functools.lru_cache(maxsize=4)  # noqa: B019 (cameras and backdrops are small frozen values)
    def _plane(self, backdrop: Backdrop) -> tuple[np.ndarray, np.ndarray]:
        """The depth (H, W) float32 of ``backdrop``'s plane at each pixel centre and where the
        ray meets its rectangle (H, W) bool; computed once per camera and backdrop."""
        right, down, forward = self.axes()
        u = (np.arange(self.width) + 0.5 - self.width / 2.0) / self.focal
        v = (np.arange(self.height) + 0.5 - self.height / 2.0) / self.focal
        rays = forward + u[None, :, None] * right + v[:, None, None] * down  # (H, W, 3), unit depth
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (backdrop.z - self.eye[2]) / rays[:, :, 2]
        x, y = self.eye[0] + t * rays[:, :, 0], self.eye[1] + t * rays[:, :, 1]
        seen = (
            (t > NEAR)
            & (t < FAR)
            & (x >= backdrop.x_range[0])
            & (x <= backdrop.x_range[1])
            & (y >= backdrop.y_range[0])
            & (y <= backdrop.y_range[1])
        )
        return np.where(seen, t, FAR).astype(np.float32), seen


LIGHT_DIRECTION = (0.3, 0.4, 1.0)


@dataclass(frozen=True)
class Backdrop:
    """A horizontal rectangle at height ``z`` (x_range × y_range, m) of one flat ``colour``
    (RGB uint8, as the renderer lights it), drawn behind every body without being rasterised:
    TinyRenderer spends about 0.25 s filling a table that covers a 1280×960 view, this mask
    a few milliseconds. The image is the same but for a few pixels where a body's edge meets
    the plane and the rasteriser's depth test was a tie (tests/sim/test_tabletop.py). A
    ``solid`` backdrop also covers what lies behind the plane (below a table top seen from
    above, e.g. the robot's legs)."""

    z: float
    x_range: tuple[float, float]
    y_range: tuple[float, float]
    colour: tuple[int, int, int]
    solid: bool = False  # also drawn over the bodies behind the plane (under a table top)
