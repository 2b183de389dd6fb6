"""Pinhole cameras over the table: rendering and the pixel <-> table-plane mapping.

Pixel coordinates ``(u, v)``: u to the right, v down, the centre of pixel ``[row, col]`` at
``(col + 0.5, row + 0.5)``. A pixel maps to the table plane by casting its ray from the
camera centre and intersecting it with ``z = TABLE_Z``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

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
        return np.column_stack([
            self.width / 2.0 + self.focal * (relative @ right) / depth,
            self.height / 2.0 + self.focal * (relative @ down) / depth,
        ])

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

    def render(self, client: int) -> tuple[np.ndarray, np.ndarray]:
        """RGB (H, W, 3) uint8 and depth (H, W) float32 metres along the optical axis."""
        view = pb.computeViewMatrix(self.eye, self.target, self.up)
        projection = pb.computeProjectionMatrixFOV(self.fov, self.width / self.height, NEAR, FAR)
        _, _, rgba, depth_buffer, _ = pb.getCameraImage(
            self.width, self.height, view, projection,
            shadow=0, lightDirection=[0.3, 0.4, 1.0], renderer=pb.ER_TINY_RENDERER,
            flags=pb.ER_NO_SEGMENTATION_MASK, physicsClientId=client,
        )
        rgb = np.asarray(rgba, dtype=np.uint8).reshape(self.height, self.width, 4)[:, :, :3].copy()
        buffer = np.asarray(depth_buffer, dtype=np.float64).reshape(self.height, self.width)
        depth = FAR * NEAR / (FAR - (FAR - NEAR) * buffer)
        return rgb, depth.astype(np.float32)
