"""Surface normals and curvature by PCA of each point's neighbourhood (paper, section
"VSL-3D": "Surface normals are estimated for each cloud using a Kd-tree and search for
neighboring points in a pre-defined radius"; Table "VSL vs VSL-3D": Normal/Curvature
Estimation).

For the neighbours within ``radius`` of a point, with covariance
``C = 1/k Σ (p_i - p̄)(p_i - p̄)^T`` and eigenvalues ``λ0 <= λ1 <= λ2``, the normal is the
eigenvector of ``λ0`` and the surface variation ("curvature", Pauly et al. 2002) is
``λ0 / (λ0 + λ1 + λ2)``. A normal's sign is not observable; it is chosen to face the
``viewpoint`` (the camera), which keeps the signs consistent across a single-view cloud.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vslsp.vsl3d.kdtree import KDTree, Neighbours

MIN_NEIGHBOURS = 3  # fewer points do not span a plane


@dataclass(frozen=True, eq=False)
class SurfaceNormals:
    """Unit ``normals`` (N, 3) (zero where a point has fewer than three neighbours) and
    ``curvature`` (N,) in [0, 1/3] (NaN there)."""

    normals: np.ndarray
    curvature: np.ndarray

    @property
    def valid(self) -> np.ndarray:
        """Mask (N,) of the points with an estimated normal."""
        return np.isfinite(self.curvature)


def estimate_normals(
    points: np.ndarray, radius: float, viewpoint: np.ndarray, tree: KDTree | None = None, max_neighbours: int = 60
) -> SurfaceNormals:
    """PCA normals of ``points`` (N, 3) over the (at most ``max_neighbours`` nearest) points
    within ``radius`` m, oriented towards ``viewpoint`` (3,) or each point's (N, 3)."""
    points = np.asarray(points, dtype=float)
    tree = tree if tree is not None and tree.points is points else KDTree(points)
    neighbours = tree.query_radius(points, radius, max_neighbours)
    return normals_from_neighbours(points, neighbours, viewpoint)


def normals_from_neighbours(points: np.ndarray, neighbours: Neighbours, viewpoint: np.ndarray) -> SurfaceNormals:
    """PCA normals of ``points`` (N, 3) over the given neighbour pairs (each point among its
    own neighbours), oriented towards ``viewpoint`` (3,) or each point's (N, 3) (a cloud fused
    from several sensors: each normal faces the sensor that saw its side)."""
    n = len(points)
    counts = neighbours.counts(n).astype(float)
    centred = points[neighbours.index] - points[neighbours.query]  # about the query: stabler sums
    outer = centred[:, :, None] * centred[:, None, :]
    sums = np.stack([np.bincount(neighbours.query, weights=centred[:, a], minlength=n) for a in range(3)], axis=1)
    second = np.stack(
        [np.bincount(neighbours.query, weights=outer[:, a, b], minlength=n) for a in range(3) for b in range(3)], axis=1
    ).reshape(n, 3, 3)
    safe = np.maximum(counts, 1.0)
    mean = sums / safe[:, None]
    covariance = second / safe[:, None, None] - mean[:, :, None] * mean[:, None, :]
    eigenvalues, eigenvectors = np.linalg.eigh(covariance)
    normals = eigenvectors[:, :, 0]
    facing = np.einsum("ij,ij->i", normals, np.asarray(viewpoint, dtype=float) - points)
    normals = np.where(facing[:, None] < 0.0, -normals, normals)
    total = eigenvalues.sum(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        curvature = np.where(total > 0.0, np.maximum(eigenvalues[:, 0], 0.0) / total, 0.0)
    enough = counts >= MIN_NEIGHBOURS
    normals[~enough] = 0.0
    curvature = np.where(enough, curvature, np.nan)
    return SurfaceNormals(normals, curvature)
