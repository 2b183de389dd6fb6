"""Point clouds from depth images, and the first steps of VSL-3D's point cloud processing
(paper, section "VSL-3D", "Point Cloud Processing"): back-projection of a depth image through
a pinhole camera, the pass-through filter that cuts the cloud to the workspace, and voxel-grid
downsampling in which "the points in a voxel are approximated with their centroid".

Clouds are plain ``(N, 3)`` float64 arrays of points in metres in the world frame. The
*k*-d tree that searches them lives in :mod:`vslsp.vsl3d.kdtree`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from vslsp.errors import InputError


@dataclass(frozen=True, eq=False)
class DepthCamera:
    """A pinhole depth camera: ``intrinsics`` K (3, 3) and ``pose`` (4, 4), the camera frame
    (x right, y down in the image, z along the optical axis) in the world frame.

    A depth image holds, per pixel, the distance along the optical axis (metres); the centre
    of pixel ``[row, col]`` is at ``(u, v) = (col + 0.5, row + 0.5)``.
    """

    intrinsics: np.ndarray
    pose: np.ndarray
    width: int
    height: int

    def __post_init__(self) -> None:
        if np.shape(self.intrinsics) != (3, 3) or np.shape(self.pose) != (4, 4):
            raise InputError("a depth camera needs 3x3 intrinsics and a 4x4 pose")

    @classmethod
    def of(cls, camera: Any) -> DepthCamera:
        """The depth camera of a simulator camera (:class:`vslsp.sim.camera.Camera`: its
        ``intrinsics()``, ``axes()`` (right, down, forward), ``eye``, ``width``, ``height``)."""
        pose = np.eye(4)
        pose[:3, :3] = np.column_stack(camera.axes())
        pose[:3, 3] = camera.eye
        return cls(np.asarray(camera.intrinsics(), dtype=float), pose, int(camera.width), int(camera.height))

    @property
    def position(self) -> np.ndarray:
        """The optical centre (3,) in the world: the viewpoint that normals face."""
        return np.asarray(self.pose, dtype=float)[:3, 3].copy()

    def back_project(self, depth: np.ndarray, max_depth: float = np.inf) -> tuple[np.ndarray, np.ndarray]:
        """World points (N, 3) of the pixels with ``0 < depth < max_depth``, and their flat
        pixel indices (N,) into the (H, W) image (``row * W + col``)."""
        depth = np.asarray(depth, dtype=float)
        if depth.shape != (self.height, self.width):
            raise InputError(
                f"depth image is {depth.shape}, the camera is {self.height}x{self.width}; "
                "pass the depth image rendered by this camera"
            )
        flat = depth.ravel()
        pixels = np.flatnonzero(np.isfinite(flat) & (flat > 0.0) & (flat < max_depth))
        rows, cols = np.divmod(pixels, self.width)
        z = flat[pixels]
        k = np.asarray(self.intrinsics, dtype=float)
        x = (cols + 0.5 - k[0, 2]) / k[0, 0] * z
        y = (rows + 0.5 - k[1, 2]) / k[1, 1] * z
        camera_points = np.column_stack([x, y, z])
        pose = np.asarray(self.pose, dtype=float)
        return camera_points @ pose[:3, :3].T + pose[:3, 3], pixels

    def project(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """World points (N, 3) to pixel coordinates (N, 2) ``(u, v)`` and depths (N,)."""
        pose = np.asarray(self.pose, dtype=float)
        camera_points = (np.atleast_2d(points) - pose[:3, 3]) @ pose[:3, :3]
        z = camera_points[:, 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            uv = camera_points[:, :2] / z[:, None]
        k = np.asarray(self.intrinsics, dtype=float)
        return uv * [k[0, 0], k[1, 1]] + [k[0, 2], k[1, 2]], z


@dataclass(frozen=True)
class Frame:
    """A VSL-3D *frame*: an axis-aligned cuboid in the world, ``lower`` (3,) to ``upper`` (3,) m."""

    lower: tuple[float, float, float]
    upper: tuple[float, float, float]

    def __post_init__(self) -> None:
        if len(self.lower) != 3 or len(self.upper) != 3 or not np.all(np.less(self.lower, self.upper)):
            raise InputError(f"a frame needs lower < upper on x, y and z, got {self.lower} .. {self.upper}")

    @classmethod
    def around(cls, points: np.ndarray, margin: float) -> Frame:
        """The bounding box of ``points`` (N, 3) grown by ``margin`` metres on every side."""
        points = np.atleast_2d(points)
        if len(points) == 0:
            raise InputError("cannot put a frame around an empty cloud")
        lower = points.min(axis=0) - margin
        upper = points.max(axis=0) + margin
        return cls(_xyz(lower), _xyz(upper))

    def contains(self, points: np.ndarray) -> np.ndarray:
        """Boolean mask (N,) of the points inside the cuboid (bounds included)."""
        points = np.atleast_2d(points)
        return np.all((points >= self.lower) & (points <= self.upper), axis=1)

    def to_dict(self) -> dict:
        return {"lower": list(self.lower), "upper": list(self.upper)}

    @classmethod
    def from_dict(cls, data: dict) -> Frame:
        return cls(_xyz(data["lower"]), _xyz(data["upper"]))


def pass_through(points: np.ndarray, frame: Frame) -> np.ndarray:
    """The points (M, 3) of ``points`` (N, 3) inside ``frame``: the pass-through filter that
    cuts the raw cloud to the workspace."""
    points = _as_cloud(points)
    return points[frame.contains(points)]


def voxel_downsample(points: np.ndarray, leaf: float) -> np.ndarray:
    """Voxel-grid downsampling: one point per occupied cube ``[i, i+1) * leaf`` (m) of the grid
    anchored at the world origin, the centroid of the points in it. Returns (M, 3), M <= N,
    ordered by voxel index (deterministic)."""
    points = _as_cloud(points)
    if not leaf > 0.0:
        raise InputError(f"voxel leaf size must be > 0 m, got {leaf}")
    if len(points) == 0:
        return points.copy()
    voxel, counts = _voxels(points, leaf)
    return _means(points, voxel, counts)


def voxel_downsample_with(points: np.ndarray, values: np.ndarray, leaf: float) -> tuple[np.ndarray, np.ndarray]:
    """:func:`voxel_downsample` of ``points`` (N, 3), and per voxel the mean of the points'
    ``values`` (N, 3) (a fused cloud's per-point viewpoints: a voxel that both sensors saw faces
    between them)."""
    points, values = _as_cloud(points), _as_cloud(values)
    if len(points) != len(values):
        raise InputError(f"{len(values)} values for {len(points)} points")
    if not leaf > 0.0:
        raise InputError(f"voxel leaf size must be > 0 m, got {leaf}")
    if len(points) == 0:
        return points.copy(), values.copy()
    voxel, counts = _voxels(points, leaf)
    return _means(points, voxel, counts), _means(values, voxel, counts)


def _voxels(points: np.ndarray, leaf: float) -> tuple[np.ndarray, np.ndarray]:
    """Each point's voxel index (N,) (voxels ordered by index) and the voxels' point counts."""
    cells = np.floor(points / leaf).astype(np.int64)  # a grid fixed in the world, as PCL's
    cells -= cells.min(axis=0)
    extent = cells.max(axis=0) + 1
    keys = (cells[:, 0] * extent[1] + cells[:, 1]) * extent[2] + cells[:, 2]
    _, voxel, counts = np.unique(keys, return_inverse=True, return_counts=True)
    return voxel, counts


def _means(values: np.ndarray, voxel: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """Per voxel the mean (M, 3) of ``values`` (N, 3)."""
    sums = np.column_stack([np.bincount(voxel, weights=values[:, axis], minlength=len(counts)) for axis in range(3)])
    return sums / counts[:, None]


def _as_cloud(points: np.ndarray) -> np.ndarray:
    points = np.asarray(points, dtype=float)
    if points.ndim != 2 or points.shape[1] != 3:
        raise InputError(f"a point cloud is an (N, 3) array, got shape {points.shape}")
    return points


def _xyz(values) -> tuple[float, float, float]:
    """Three coordinates as floats."""
    x, y, z = values
    return float(x), float(y), float(z)
