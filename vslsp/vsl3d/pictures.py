"""Pictures of VSL-3D for the reports (paper, section "VSL-3D", the figures of the table
cleaning: the RGB view with the observation's frame, the point cloud segmented into objects):
the frame's cuboid and the grasp drawn on the RGB view, a rendered oblique view of a cloud
coloured by its Euclidean segments, and the clouds themselves (decimated, ``.npz``) for a 3-D
viewer: each demonstration's pre- and post-action scene with the object getObject found, and
each reproduction's capture with the matched observation (:func:`trial_clouds`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import cv2
import numpy as np

from vslsp.outputs import atomic_file
from vslsp.vsl3d.cloud import DepthCamera, Frame, voxel_downsample
from vslsp.vsl3d.grasping import Grasp
from vslsp.vsl3d.kdtree import KDTree
from vslsp.vsl3d.vsl import OPERATED, MovedObject, euclidean_clusters

SEGMENT_GAP = 0.01  # points closer than this are one segment in the cloud picture
PALETTE = np.array(
    [
        [230, 25, 75],
        [60, 180, 75],
        [0, 130, 200],
        [245, 130, 48],
        [145, 30, 180],
        [70, 240, 240],
        [240, 50, 230],
        [210, 245, 60],
        [128, 128, 0],
        [0, 0, 128],
    ],
    dtype=np.uint8,
)


def draw_frame(rgb: np.ndarray, camera: DepthCamera, frame: Frame, colour: tuple[int, int, int]) -> np.ndarray:
    """The RGB image (H, W, 3) with the frame's cuboid drawn on it."""
    corners = np.array(
        [
            [x, y, z]
            for x in (frame.lower[0], frame.upper[0])
            for y in (frame.lower[1], frame.upper[1])
            for z in (frame.lower[2], frame.upper[2])
        ]
    )
    uv, _ = camera.project(corners)
    image = np.ascontiguousarray(rgb.copy())
    for a in range(8):
        for b in range(a + 1, 8):
            if bin(a ^ b).count("1") == 1:  # corners differing in one coordinate share an edge
                cv2.line(image, tuple(int(v) for v in uv[a]), tuple(int(v) for v in uv[b]), colour, 1, cv2.LINE_AA)
    return image


def draw_grasp(
    rgb: np.ndarray, camera: DepthCamera, grasp: Grasp, colour: tuple[int, int, int] = (255, 200, 0)
) -> np.ndarray:
    """The RGB image (H, W, 3) with the grasp drawn: the two fingertips across the object's
    width along the closing axis, joined, and the grasp point."""
    axis = np.array([np.cos(grasp.theta), np.sin(grasp.theta), 0.0])
    half = grasp.width / 2.0 + 0.008
    tips = np.array([grasp.point - half * axis, grasp.point + half * axis, grasp.point])
    uv, _ = camera.project(tips)
    image = np.ascontiguousarray(rgb.copy())
    a, b, c = (tuple(int(v) for v in p) for p in uv)
    cv2.line(image, a, b, colour, 2, cv2.LINE_AA)
    for tip in (a, b):
        cv2.circle(image, tip, 4, colour, -1, cv2.LINE_AA)
    cv2.drawMarker(image, c, (255, 255, 255), cv2.MARKER_CROSS, 10, 1, cv2.LINE_AA)
    return image


def cloud_view(points: np.ndarray, size: tuple[int, int] = (480, 640), elevation_deg: float = 60.0) -> np.ndarray:
    """An RGB picture (H, W, 3) of ``points`` (N, 3) seen obliquely from the robot's side
    (elevation ``elevation_deg``), each Euclidean segment in its own colour, nearer points drawn
    over farther ones."""
    height, width = size
    image = np.full((height, width, 3), 255, dtype=np.uint8)
    if len(points) == 0:
        return image
    labels = euclidean_clusters(points, SEGMENT_GAP)
    colours = PALETTE[labels % len(PALETTE)]
    e = np.radians(elevation_deg)
    centre = points.mean(axis=0)
    p = points - centre
    # View from -x (the robot's side) and above: image right is -y, image up mixes z and x.
    u = -p[:, 1]
    v = p[:, 2] * np.cos(e) + p[:, 0] * np.sin(e)
    depth = p[:, 0] * np.cos(e) - p[:, 2] * np.sin(e)
    scale = 0.9 * min(width / max(np.ptp(u), 1e-6), height / max(np.ptp(v), 1e-6))
    cols = np.clip(((u - (u.max() + u.min()) / 2) * scale + width / 2).astype(int), 0, width - 2)
    rows = np.clip((height / 2 - (v - (v.max() + v.min()) / 2) * scale).astype(int), 0, height - 2)
    for k in np.argsort(-depth, kind="stable"):  # far first
        image[rows[k] : rows[k] + 2, cols[k] : cols[k] + 2] = colours[k]
    return image


def draw_moves(
    pre: np.ndarray, post: np.ndarray, camera: DepthCamera, moved: MovedObject, names: Sequence[str | None] = ()
) -> tuple[np.ndarray, np.ndarray]:
    """The pre- and post-action RGB views (H, W, 3) with the slip detection's finding marked: each
    object the tutor disturbed in orange (its frame before on ``pre``, after on ``post``), and
    ``names`` (of ``moved.moves``, in order; the report's truth) written at the frames: which
    object was operated, which disturbed."""
    pre, post = np.ascontiguousarray(pre.copy()), np.ascontiguousarray(post.copy())
    for index, move in enumerate(moved.moves):
        name = names[index] if index < len(names) and names[index] else "object"
        before, after = move.frames
        colours = ((255, 0, 0), (0, 160, 0)) if move.role == OPERATED else (DISTURBED_COLOUR, DISTURBED_COLOUR)
        for image, frame, colour in ((pre, before, colours[0]), (post, after, colours[1])):
            if move.role != OPERATED:
                image[:] = draw_frame(image, camera, frame, colour)
            corner = np.array([[frame.lower[0], frame.lower[1], frame.upper[2]]])
            uv, _ = camera.project(corner)
            text = f"{move.role}: {name}"
            (width, _), _ = cv2.getTextSize(text, cv2.FONT_HERSHEY_SIMPLEX, 0.4, 1)
            x, y = min(max(0, int(uv[0, 0])), image.shape[1] - width - 2), max(12, int(uv[0, 1]) - 4)
            cv2.putText(image, text, (x, y), cv2.FONT_HERSHEY_SIMPLEX, 0.4, colour, 1, cv2.LINE_AA)
    return pre, post


def trial_pictures(
    demonstration: list[np.ndarray],
    matched: list[np.ndarray],
    cloud: np.ndarray | None,
    demonstrated_final: np.ndarray,
    reproduced_final: np.ndarray,
    clouds: Mapping[str, dict[str, np.ndarray]] | None = None,
) -> dict:
    """A VSL-3D trial's pictures for the report: the demonstration's views, the matched views,
    the cloud view (the final scene where no cloud was seen), the final scenes side by side and
    the ``clouds`` for a 3-D view (:func:`trial_clouds`)."""
    final = np.hstack([demonstrated_final, reproduced_final])
    return {
        "demonstration": demonstration,
        "matched": matched,
        "cloud": cloud if cloud is not None else final,
        "final": final,
        "clouds": dict(clouds or {}),
    }


#: A report's cloud is decimated to this voxel (m), and evenly to at most this many points.
CLOUD_VOXEL = 0.004
MAX_CLOUD_POINTS = 12_000


#: A report cloud's labels: the rest of the scene, the object (getObject's, or the match), an
#: object the tutor disturbed (the slip detection's finding).
SCENE_LABEL, OBJECT_LABEL, DISTURBED_LABEL = 0, 1, 2
DISTURBED_COLOUR = (255, 140, 0)  # a disturbed object's frames on the RGB views (orange)


def labelled_cloud(
    scene: np.ndarray, found: np.ndarray, caption: str, disturbed: Sequence[np.ndarray] = ()
) -> dict[str, np.ndarray]:
    """A cloud for the report: ``scene`` (N, 3) and the object's points ``found`` (M, 3), both
    decimated; ``labels`` (K,) is 1 on the object's points and 0 on the rest of the scene (the
    scene's points within a voxel of the object's are the object's), 2 on the scene's points
    within a voxel of a ``disturbed`` object's (each (L, 3))."""
    found = voxel_downsample(found, CLOUD_VOXEL) if len(found) else np.zeros((0, 3))
    rest = voxel_downsample(scene, CLOUD_VOXEL) if len(scene) else np.zeros((0, 3))
    if len(found) and len(rest):
        gap, _ = KDTree(found).query(rest, 1, CLOUD_VOXEL)
        rest = rest[gap[:, 0] > CLOUD_VOXEL]
    points = np.vstack([rest, found])
    labels = np.r_[np.zeros(len(rest), np.uint8), np.ones(len(found), np.uint8)]
    for other in disturbed:
        if len(other) and len(rest):
            gap, _ = KDTree(np.asarray(other, dtype=float)).query(rest, 1, CLOUD_VOXEL)
            labels[: len(rest)][gap[:, 0] <= CLOUD_VOXEL] = DISTURBED_LABEL
    keep = slice(None, None, max(1, -(-len(points) // MAX_CLOUD_POINTS)))
    return {"points": points[keep].astype(np.float32), "labels": labels[keep], "caption": np.array(caption)}


def trial_clouds(
    demonstrated: Sequence[MovedObject | None], reproduced: Mapping[int, Any]
) -> dict[str, dict[str, np.ndarray]]:
    """The clouds a person wants to turn in 3-D, by name: per demonstrated operation J (from 1)
    ``demonstration_J_pre`` and ``demonstration_J_post`` (the scene getObject was given, the
    object it found labelled), and per reproduced operation (``reproduced``: the operation's
    index from 0 -> its record, a :class:`vslsp.experiments.cloud_reproduction.Reproduction`)
    ``reproduction_J`` (the last attempt's capture, the matched observation labelled where
    findBestMatch put it)."""
    clouds: dict[str, dict[str, np.ndarray]] = {}
    for number, moved in enumerate(demonstrated, start=1):
        if moved is not None and moved.scenes is not None:
            pre, post = moved.scenes
            caption = f"demonstration {number}: the %s-action scene, the object getObject found (red)"
            disturbed = moved.disturbed
            if disturbed:
                caption += ", the objects the tutor disturbed (orange)"
            clouds[f"demonstration_{number}_pre"] = labelled_cloud(
                pre, moved.pre.points, caption % "pre", [m.before for m in disturbed]
            )
            clouds[f"demonstration_{number}_post"] = labelled_cloud(
                post, moved.post.points, caption % "post", [m.after for m in disturbed]
            )
    for index, record in sorted(reproduced.items()):
        attempt = record.last
        if attempt is not None and attempt.match is not None:
            caption = f"reproduction {index + 1}: the capture, the matched observation (red) where it was found"
            clouds[f"reproduction_{index + 1}"] = labelled_cloud(attempt.world.points, attempt.match.points, caption)
    return clouds


def write_clouds(folder: Path, clouds: Mapping[str, dict[str, np.ndarray]]) -> dict[str, list[str]]:
    """Write each cloud of :func:`trial_clouds` to ``folder/clouds/NAME.npz`` (no pickle: ``points``
    (N, 3) float32, ``labels`` (N,) uint8, ``caption``); ``{"clouds": [paths relative to folder]}``."""
    if not clouds:
        return {}
    (folder / "clouds").mkdir(parents=True, exist_ok=True)
    written = []
    for name, cloud in clouds.items():
        written.append(f"clouds/{name}.npz")
        with atomic_file(folder / written[-1]) as stream:
            np.savez_compressed(stream, points=cloud["points"], labels=cloud["labels"], caption=cloud["caption"])
    return {"clouds": written}
