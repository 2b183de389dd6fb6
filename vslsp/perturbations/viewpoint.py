"""The camera's side of a perturbation: a camera moved, turned, nearer or farther.

The turn is about the point the camera looks at (it orbits the table's centre of view, still
looking at it, as a camera re-mounted elsewhere over the same table would), the shift moves the
camera and that point together in the table's plane, and the scale brings the camera nearer
(``scale`` > 1: objects larger in the image) or farther along its line of sight. For a camera
over a planar board (the house-roof board, drawn at 1 px per board unit by a camera straight
above it) :func:`board_homography` is the map from the board to the moved camera's image: the
reproduction sees the board through it and, knowing the camera's calibration, maps what it sees
back to the board (:func:`to_board`).
"""

from __future__ import annotations

import cv2
import numpy as np

from vslsp.perturbations.spec import Drawn

Vector = tuple[float, float, float]


def rotation(axis: Vector | np.ndarray, degrees: float) -> np.ndarray:
    """The (3, 3) rotation by ``degrees`` about unit ``axis`` (Rodrigues)."""
    vector = np.asarray(axis, dtype=float)
    vector = vector / np.linalg.norm(vector) * np.radians(degrees)
    matrix, _ = cv2.Rodrigues(vector)
    return np.asarray(matrix, dtype=float)


def moved_view(
    eye: Vector, target: Vector, up: Vector, drawn: Drawn, metres: float = 1.0
) -> tuple[Vector, Vector, Vector]:
    """The camera ``eye`` looking at ``target`` (``up`` its up vector) moved by ``drawn``: turned
    by ``drawn.levels.camera`` deg about ``drawn.turn_axis`` around the target, shifted by
    ``drawn.shift`` (m; times ``metres``, the world's units per metre), and brought nearer by
    ``drawn.levels.scale``. Unchanged when the draw moves no camera."""
    levels = drawn.levels
    if not levels.camera and levels.scale == 1.0:
        return eye, target, up
    turn = rotation(drawn.turn_axis, levels.camera) if levels.camera else np.eye(3)
    centre = np.asarray(target, dtype=float)
    sight = turn @ (np.asarray(eye, dtype=float) - centre) / levels.scale
    shift = np.asarray(drawn.shift, dtype=float) * metres
    new_up = turn @ np.asarray(up, dtype=float)
    moved_centre = centre + shift
    return _tuple(moved_centre + sight), _tuple(moved_centre), _tuple(new_up)


def _tuple(vector: np.ndarray) -> Vector:
    return (float(vector[0]), float(vector[1]), float(vector[2]))


def board_homography(width: int, height: int, distance: float, drawn: Drawn, units_per_metre: float) -> np.ndarray:
    """The (3, 3) map from board pixels to the moved camera's image, for a board of ``width`` x
    ``height`` px seen by a camera ``distance`` px straight above its centre with a focal length
    of ``distance`` px (so that, unmoved, board pixel = image pixel: the identity)."""
    centre = (width / 2.0, height / 2.0, 0.0)
    eye, target, up = moved_view(
        (width / 2.0, height / 2.0, -distance), centre, (0.0, -1.0, 0.0), drawn, units_per_metre
    )
    forward = np.subtract(target, eye)
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    down = np.cross(forward, right)
    world_to_camera = np.vstack([right, down, forward])
    intrinsics = np.array([[distance, 0.0, width / 2.0], [0.0, distance, height / 2.0], [0.0, 0.0, 1.0]])
    translation = -world_to_camera @ np.asarray(eye)
    projection = intrinsics @ np.column_stack([world_to_camera[:, 0], world_to_camera[:, 1], translation])
    return projection / projection[2, 2]


def view(image: np.ndarray, homography: np.ndarray, margin: int = 0) -> np.ndarray:
    """The board ``image`` as the moved camera sees it: its sensor the board's size and ``margin``
    px more on each side (a camera whose view reaches past the board, so a moved one still sees
    it whole); past the board, the board's edge colour."""
    height, width = image.shape[:2]
    return cv2.warpPerspective(
        image,
        _framed(homography, margin),
        (width + 2 * margin, height + 2 * margin),
        flags=cv2.INTER_LINEAR,
        borderValue=_edge_colour(image),
    )


def to_board(image: np.ndarray, homography: np.ndarray, margin: int = 0) -> np.ndarray:
    """The moved camera's ``image`` (from :func:`view` with the same ``margin``) mapped back onto
    the board through its calibration (``homography``, board to image): the view a reproduction
    matches in board coordinates."""
    height, width = image.shape[0] - 2 * margin, image.shape[1] - 2 * margin
    return cv2.warpPerspective(
        image,
        _framed(homography, margin),
        (width, height),
        flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
        borderValue=_edge_colour(image),
    )


def _framed(homography: np.ndarray, margin: int) -> np.ndarray:
    return np.array([[1.0, 0.0, margin], [0.0, 1.0, margin], [0.0, 0.0, 1.0]]) @ homography


def _edge_colour(image: np.ndarray) -> tuple[int, ...]:
    return tuple(int(c) for c in np.median(image[[0, -1]].reshape(-1, image.shape[2]), axis=0))
