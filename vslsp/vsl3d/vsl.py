"""VSL-3D: Visuospatial Skill Learning on point clouds (paper, section "VSL-3D: An Extension
to 3D Tasks"; Algorithm 1 with clouds for images).

- A *world* cloud :class:`WorldCloud` is one depth capture, back-projected, cut to the
  workspace by the pass-through filter (which also drops the table top) and voxelised at 2 mm.
- ``getObject`` (Algorithm 1, line 7) is :func:`get_object`: the pre- and post-action clouds
  are subtracted by KNN search ("voxelized at a resolution of 2 mm and the distance threshold
  for the KNN-search is set to 1 cm"); a point with no counterpart within the threshold has
  changed, unless the other capture could not see it (something stood in front of it there):
  that is occlusion by the moved object, not motion. The changed points are grouped by
  Euclidean clustering; exactly one object must have left one place and arrived at one place.
  Its *pre-* and *post-action observations* are the changed points in cuboid *frames*, and its
  6-DoF motion (4x4) comes from registering one onto the other (FPFH + RANSAC or SAC-IA, and
  ICP from 12 turns about the vertical; the pose that fits best without floating in front of
  what the post-action capture saw wins).
- ``findBestMatch`` (Algorithm 1, lines 13-14) is in :mod:`vslsp.vsl3d.matching`.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import cached_property
from pathlib import Path

import cv2
import numpy as np

from vslsp.errors import InputError, TaskFailed
from vslsp.files import load_npz
from vslsp.outcomes import NoMatch
from vslsp.outputs import atomic_file
from vslsp.stages import in_stage
from vslsp.vsl3d.alignment import align
from vslsp.vsl3d.cloud import DepthCamera, Frame, pass_through, voxel_downsample, voxel_downsample_with
from vslsp.vsl3d.kdtree import KDTree
from vslsp.vsl3d.parameters import DEFAULT_CLOUD_MATCHING, CloudMatching
from vslsp.vsl3d.registration import Registration, transform_error

VOXEL = 0.002  # the paper's voxel size
MAX_OBSERVATION_BYTES = 512_000_000  # a saved observation's arrays, decoded (a 4096x4096 view's points: 400 MB)
# The default rules' figures, for the modules that read them by name (see CloudMatching).
CHANGE_THRESHOLD = DEFAULT_CLOUD_MATCHING.change_threshold
CLUSTER_DISTANCE = DEFAULT_CLOUD_MATCHING.cluster_distance
MIN_CLUSTER_POINTS = DEFAULT_CLOUD_MATCHING.min_cluster_points
FRAME_MARGIN = DEFAULT_CLOUD_MATCHING.frame_margin


@dataclass(frozen=True, eq=False)
class WorldCloud:
    """The world W as one capture: ``points`` (N, 3) (pass-through filtered, voxelised), the raw
    ``depth`` (H, W) it came from and the ``camera`` (for visibility and the viewpoint);
    ``floor`` (m) is the pass-through's lower bound, just above the table top: the table is
    solid, nothing lies under it.

    A capture of several sensors at known poses (:meth:`capture` with ``others``) is one fused
    cloud: ``others`` holds the other sensors' (depth, camera), and ``viewpoints`` (N, 3) each
    point's viewpoint (the mean of the sensors that saw its voxel: normals face the sensor that
    saw their side). What any sensor saw through is free space, and a point any sensor could
    have seen was visible (:meth:`seen_through`, :meth:`visible`)."""

    points: np.ndarray
    depth: np.ndarray
    camera: DepthCamera
    floor: float = -np.inf
    others: tuple[tuple[np.ndarray, DepthCamera], ...] = ()
    viewpoints: np.ndarray | None = None
    silhouette_px: int = DEFAULT_CLOUD_MATCHING.silhouette_px  # see CloudMatching.silhouette_px

    @classmethod
    def capture(
        cls,
        depth: np.ndarray,
        camera: DepthCamera,
        workspace: Frame,
        voxel: float = VOXEL,
        others: tuple[tuple[np.ndarray, DepthCamera], ...] = (),
    ) -> WorldCloud:
        """Back-project ``depth`` (H, W), keep what lies in ``workspace``, voxelise at ``voxel`` m.
        With ``others`` (the other sensors' depth (H', W') and camera, each at its known pose):
        every view is back-projected into the world frame by its camera's pose, the clouds are
        concatenated, cut to ``workspace`` and voxelised together (where the views overlap the
        density stays that of one view)."""
        points, _ = camera.back_project(depth)
        floor = float(workspace.lower[2])
        if not others:
            return cls(
                voxel_downsample(pass_through(points, workspace), voxel), np.asarray(depth, dtype=float), camera, floor
            )
        clouds = [pass_through(points, workspace)]  # each view cut first: a fifth of its pixels stays
        viewpoints = [np.broadcast_to(camera.position, clouds[0].shape)]
        for other_depth, other_camera in others:
            clouds.append(pass_through(other_camera.back_project(other_depth)[0], workspace))
            viewpoints.append(np.broadcast_to(other_camera.position, clouds[-1].shape))
        fused, seen_from = voxel_downsample_with(np.vstack(clouds), np.vstack(viewpoints), voxel)
        views = tuple((np.asarray(d, dtype=float), c) for d, c in others)
        return cls(fused, np.asarray(depth, dtype=float), camera, floor, views, seen_from)

    @property
    def viewpoint(self) -> np.ndarray:
        """The viewpoint that normals face: the camera's centre (3,), or with several sensors
        each point's (N, 3)."""
        return self.camera.position if self.viewpoints is None else self.viewpoints

    def viewpoint_of(self, mask: np.ndarray) -> np.ndarray:
        """The viewpoint of the points ``self.points[mask]``: (3,) for one sensor, else (K, 3)."""
        return self.camera.position if self.viewpoints is None else self.viewpoints[mask]

    def viewpoint_at(self, points: np.ndarray) -> np.ndarray:
        """The viewpoint of ``points`` (K, 3), points of this cloud (a segment of it): (3,) for
        one sensor, else each one's (K, 3), that of the cloud's point nearest to it."""
        if self.viewpoints is None:
            return self.camera.position
        _, nearest = KDTree(self.points).query(np.asarray(points, dtype=float), 1)
        return self.viewpoints[nearest[:, 0]]

    def without(self, near: np.ndarray, distance: float = FRAME_MARGIN) -> WorldCloud:
        """This capture with its points within ``distance`` m of any of ``near`` (K, 3) left out
        (the raw depth, and so what the sensor saw, stays)."""
        if len(near) == 0 or len(self.points) == 0:
            return self
        gap, _ = KDTree(np.asarray(near, dtype=float)).query(self.points, 1, distance)
        kept = gap[:, 0] > distance
        if self.viewpoints is None:
            return replace(self, points=self.points[kept])
        return replace(self, points=self.points[kept], viewpoints=self.viewpoints[kept])

    def visible(self, points: np.ndarray, tolerance: float = CHANGE_THRESHOLD) -> np.ndarray:
        """Mask (N,) of points this capture could have seen: inside the image and not behind
        what it saw at their pixel (by more than ``tolerance`` m); with several sensors, any of them."""
        seen = np.zeros(len(points), dtype=bool)
        for view in range(1 + len(self.others)):
            inside, z, depth = self._depth_at(points, view=view)
            seen[inside] |= (depth <= 0.0) | (depth >= z[inside] - tolerance)
        return seen

    def seen_through(self, points: np.ndarray, tolerance: float = CHANGE_THRESHOLD) -> np.ndarray:
        """Mask (N,) of points that cannot be there: this capture (any of its sensors) saw a
        surface more than ``tolerance`` m behind them along their pixel's ray, i.e. free space
        where they are, or they lie more than ``tolerance`` under the :attr:`floor` (inside the
        table: a tipped pose of a box sinks an edge into it, where no ray can tell)."""
        through = np.asarray(points)[:, 2] < self.floor - tolerance
        for view, around in enumerate(self._nearest_around):
            inside, z, nearest = self._depth_at(points, around, view)
            through[inside] |= np.isfinite(nearest) & (nearest > z[inside] + tolerance)
        return through

    @cached_property
    def _nearest_around(self) -> tuple[np.ndarray, ...]:
        """Per sensor (H, W): the nearest depth seen within :attr:`silhouette_px` pixels of each
        pixel (inf where nothing was seen around it)."""
        size = 2 * self.silhouette_px + 1
        return tuple(
            cv2.erode(
                np.where(depth > 0.0, depth, np.inf).astype(np.float32),
                np.ones((size, size), np.uint8),
                borderType=cv2.BORDER_REPLICATE,
            )
            for depth in (self.depth, *(d for d, _ in self.others))
        )

    def _depth_at(
        self, points: np.ndarray, image: np.ndarray | None = None, view: int = 0
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Which points project into sensor ``view``'s image (N,), their depths (N,), and its
        captured depth (or ``image`` (H, W)'s value) at their pixels (for those inside)."""
        depth, camera = (self.depth, self.camera) if view == 0 else self.others[view - 1]
        uv, z = camera.project(points)
        cols, rows = np.floor(uv[:, 0]).astype(np.int64), np.floor(uv[:, 1]).astype(np.int64)
        inside = (z > 0) & (cols >= 0) & (cols < camera.width) & (rows >= 0) & (rows < camera.height)
        return inside, z, (depth if image is None else image)[rows[inside], cols[inside]]


@dataclass(frozen=True, eq=False)
class CloudObservation:
    """A VSL-3D observation: the object's ``points`` (N, 3) in the world, the ``frame`` (cuboid)
    they were captured in, and the ``viewpoint`` (3,) of the sensor (of a fused capture, each
    point's (N, 3))."""

    points: np.ndarray
    frame: Frame
    viewpoint: np.ndarray

    @property
    def centroid(self) -> np.ndarray:
        return self.points.mean(axis=0)

    def save(self, path: str | Path) -> None:
        """Write to an ``.npz`` file (no pickle)."""
        with atomic_file(path) as stream:
            np.savez_compressed(
                stream,
                points=self.points,
                lower=np.asarray(self.frame.lower),
                upper=np.asarray(self.frame.upper),
                viewpoint=self.viewpoint,
            )

    @classmethod
    def load(cls, path: str | Path) -> CloudObservation:
        try:
            data = load_npz(path, "VSL-3D observation", MAX_OBSERVATION_BYTES)
            points, lower, upper, viewpoint = (data[key] for key in ("points", "lower", "upper", "viewpoint"))
        except (InputError, KeyError) as error:
            raise InputError(
                f"cannot read a VSL-3D observation from {path}: {error}; pass a file written by CloudObservation.save"
            ) from error
        return cls(points, Frame(tuple(lower), tuple(upper)), viewpoint)


OPERATED, DISTURBED = "operated", "disturbed"


@dataclass(frozen=True, eq=False)
class Move:
    """One object that moved in an operation (:mod:`vslsp.vsl.slips.clouds`): its changed points that
    ``left`` (K, 3) and that ``arrived`` (L, 3), the object itself ``before`` (its pre-action
    points) and ``after`` (its post-action points), and its ``role``: :data:`OPERATED` or
    :data:`DISTURBED` (the tutor's slip)."""

    left: np.ndarray
    arrived: np.ndarray
    before: np.ndarray
    after: np.ndarray
    role: str

    @property
    def sides(self) -> tuple[np.ndarray, np.ndarray]:
        """The object's points before and after (its changed points where the capture had none
        of it on that side: an object that came from nowhere in view, or went)."""
        before = self.before if len(self.before) else self.left
        after = self.after if len(self.after) else self.arrived
        return (before if len(before) else after), (after if len(after) else before)

    @property
    def shift(self) -> float:
        """How far (m) the middle of the object's points moved in the table plane."""
        middle = [(p.min(axis=0) + p.max(axis=0)) / 2.0 for p in self.sides]
        return float(np.linalg.norm(middle[1][:2] - middle[0][:2]))

    @property
    def frames(self) -> tuple[Frame, Frame]:
        """The cuboids around the object before and after (the report's pictures)."""
        before, after = self.sides
        return Frame.around(before, FRAME_MARGIN), Frame.around(after, FRAME_MARGIN)

    def to_dict(self) -> dict:
        before, after = self.sides
        return {
            "role": self.role,
            "pre_centroid": np.round(before.mean(axis=0), 4).tolist(),
            "post_centroid": np.round(after.mean(axis=0), 4).tolist(),
            "shift_mm": round(1000 * self.shift, 1),
            "changed_points": [len(self.left), len(self.arrived)],
        }


@dataclass(frozen=True, eq=False)
class MovedObject:
    """What ``getObject`` finds: the object's ``pre`` and ``post`` observations and its motion,
    ``registration.transform`` (4, 4), taking the pre points onto the post points; ``scenes``:
    the pre- and post-action worlds' points it was found in (the report's clouds); ``moves``:
    with the slip detection, every object that moved, the operated one first (empty without)."""

    pre: CloudObservation
    post: CloudObservation
    registration: Registration
    scenes: tuple[np.ndarray, np.ndarray] | None = field(default=None, repr=False)
    moves: tuple[Move, ...] = field(default=(), repr=False)

    @property
    def disturbed(self) -> tuple[Move, ...]:
        """The objects the tutor disturbed (the slip detection's finding; empty without it)."""
        return tuple(move for move in self.moves if move.role == DISTURBED)

    @property
    def transform(self) -> np.ndarray:
        return self.registration.transform

    def to_dict(self) -> dict:
        _, angle = transform_error(self.transform, np.eye(4), self.pre.centroid)
        return {
            "pre": {
                "frame": self.pre.frame.to_dict(),
                "centroid": self.pre.centroid.tolist(),
                "points": len(self.pre.points),
            },
            "post": {
                "frame": self.post.frame.to_dict(),
                "centroid": self.post.centroid.tolist(),
                "points": len(self.post.points),
            },
            "transform": self.transform.tolist(),
            "rotation_deg": float(angle),
            "fitness": self.registration.fitness,
            "rmse": self.registration.rmse,
            "method": self.registration.method,
        }


def changed_points(reference: WorldCloud, other: WorldCloud, threshold: float = CHANGE_THRESHOLD) -> np.ndarray:
    """Mask (N,) of ``other``'s points with no point of ``reference`` within ``threshold`` m
    that ``reference`` could have seen: what is in ``other`` and not in ``reference``."""
    if len(other.points) == 0:
        return np.zeros(0, dtype=bool)
    if len(reference.points) == 0:
        return reference.visible(other.points, threshold)
    distance, _ = KDTree(reference.points).query(other.points, 1, threshold)
    return (distance[:, 0] > threshold) & reference.visible(other.points, threshold)


def euclidean_clusters(points: np.ndarray, distance: float) -> np.ndarray:
    """Connected components (labels (N,), 0..C-1, largest first) of the graph joining points
    closer than ``distance`` (computed on a voxel grid of ``distance / 4``: each point takes its
    voxel's label)."""
    if len(points) == 0:
        return np.zeros(0, dtype=np.int64)
    grid = voxel_downsample(points, distance / 4.0)
    pairs = KDTree(grid).query_radius(grid, distance)
    labels = np.arange(len(grid))
    while True:  # min-label propagation with pointer jumping
        updated = labels.copy()
        np.minimum.at(updated, pairs.query, labels[pairs.index])
        updated = updated[updated]
        if np.array_equal(updated, labels):
            break
        labels = updated
    _, nearest = KDTree(grid).query(points, 1)
    _, labels, sizes = np.unique(labels[nearest[:, 0]], return_inverse=True, return_counts=True)
    rank = np.empty_like(sizes)
    rank[np.argsort(-sizes, kind="stable")] = np.arange(len(sizes))
    return rank[labels]


@in_stage("perception")
def get_object(
    pre: WorldCloud,
    post: WorldCloud,
    *,
    threshold: float | None = None,
    min_points: int | None = None,
    method: str = "prerejective_ransac",
    seed: int = 0,
    parameters: CloudMatching = DEFAULT_CLOUD_MATCHING,
) -> MovedObject:
    """The one object the tutor moved between the ``pre`` and ``post`` captures, its pre- and
    post-action observations and its 6-DoF motion, by the rules ``parameters`` (``threshold``
    and ``min_points``, when given, stand for its ``change_threshold`` and
    ``min_cluster_points``). Raises :class:`TaskFailed` when nothing or more than one object
    moved."""
    threshold = parameters.change_threshold if threshold is None else threshold
    min_points = parameters.min_cluster_points if min_points is None else min_points
    left = pre.points[changed_points(post, pre, threshold)]  # in pre, gone from post
    arrived = post.points[changed_points(pre, post, threshold)]
    points = np.vstack([left, arrived])
    side = np.r_[np.zeros(len(left), dtype=bool), np.ones(len(arrived), dtype=bool)]
    labels = euclidean_clusters(points, parameters.cluster_distance)
    regions = [
        label for label in range(labels.max() + 1 if len(labels) else 0) if np.sum(labels == label) >= min_points
    ]
    if not regions:
        raise TaskFailed(
            f"nothing moved: no region of more than {min_points} points changed by "
            f"{threshold * 100:.0f} cm between the pre- and post-action clouds; "
            "capture the post-action cloud after the tutor has moved an object",
            cause="nothing moved",
        )
    leaving = [r for r in regions if np.sum((labels == r) & ~side) >= min_points]
    arriving = [r for r in regions if np.sum((labels == r) & side) >= min_points]
    if len(leaving) > 1 or len(arriving) > 1:
        where = "; ".join(
            f"{'left' if r in leaving else ''}{'/' if r in leaving and r in arriving else ''}"
            f"{'arrived' if r in arriving else ''} at {_centre(points[labels == r])}"
            for r in regions
        )
        raise TaskFailed(
            f"several objects moved ({where}); VSL-3D learns one object per operation: demonstrate one move at a time",
            cause="several objects moved",
        )
    if not leaving or not arriving:
        missing = "left its place" if not leaving else "arrived anywhere"
        raise TaskFailed(
            f"an object changed at {_centre(points[np.isin(labels, regions)])} but nothing "
            f"{missing} in view; keep the moved object inside the workspace and in view"
        )
    before = points[(labels == leaving[0]) & ~side]
    after = points[(labels == arriving[0]) & side]
    return moved_object(pre, post, before, after, method=method, seed=seed, parameters=parameters)


def moved_object(
    pre: WorldCloud,
    post: WorldCloud,
    before: np.ndarray,
    after: np.ndarray,
    *,
    method: str,
    seed: int,
    parameters: CloudMatching = DEFAULT_CLOUD_MATCHING,
) -> MovedObject:
    """The object whose pre-action observation is ``before`` (N, 3) (points of ``pre``) and
    post-action observation ``after`` (M, 3) (of ``post``), with its motion registered from one
    onto the other. Raises :class:`TaskFailed` when no motion fits."""
    viewpoint, post_viewpoint = pre.viewpoint_at(before), post.viewpoint_at(after)
    registration = align(
        before,
        after,
        viewpoint,
        post_viewpoint,
        method=method,
        seed=seed,
        turns=parameters.turns,
        seen_through=post.seen_through,
        source_seen_through=pre.seen_through,
        target_visible=post.visible,
        min_fitness=parameters.motion_min_fitness,
        refined=parameters.motion_refined,
    )
    if isinstance(registration, NoMatch):  # the demonstration itself cannot be read
        raise TaskFailed(registration.reason)
    return MovedObject(
        CloudObservation(before, Frame.around(before, parameters.frame_margin), viewpoint),
        CloudObservation(after, Frame.around(after, parameters.frame_margin), post_viewpoint),
        registration,
        (pre.points, post.points),
    )


def _centre(points: np.ndarray) -> str:
    x, y, z = points.mean(axis=0)
    return f"({x:.3f}, {y:.3f}, {z:.3f}) m"
