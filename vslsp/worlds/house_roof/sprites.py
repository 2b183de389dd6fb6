"""The house-and-roof world of the paper's simulation ("Methodology", "Simulation": three
identical blue house bodies and three brown roofs), drawn with OpenCV, either axis-aligned
(:func:`houses_world`) or as sprites composited at any pose (:func:`paste`).

Images whose truth is known exactly, without a simulator: the house-roof task
(:mod:`vslsp.worlds.house_roof.board`), its tests and benchmarks draw its world with them.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import cv2
import numpy as np

# -- the house-and-roof world -------------------------------------------------------------------
BODY_SIZE = 60  # px, side of a house body; a roof is as wide and 30 px high


def house_body(image: np.ndarray, top_left: tuple[int, int]) -> None:
    """Draw a blue house body (60×60 px, two windows and a door) with its top-left corner at (x, y)."""
    x, y = top_left
    cv2.rectangle(image, (x, y), (x + BODY_SIZE - 1, y + BODY_SIZE - 1), (40, 80, 200), -1)
    cv2.rectangle(image, (x, y), (x + BODY_SIZE - 1, y + BODY_SIZE - 1), (20, 40, 110), 2)
    for wx in (x + 8, x + 36):
        cv2.rectangle(image, (wx, y + 10), (wx + 15, y + 25), (235, 235, 210), -1)
        cv2.line(image, (wx + 8, y + 10), (wx + 8, y + 25), (20, 40, 110), 1)
        cv2.line(image, (wx, y + 18), (wx + 15, y + 18), (20, 40, 110), 1)
    cv2.rectangle(image, (x + 24, y + 34), (x + 35, y + BODY_SIZE - 3), (120, 70, 30), -1)


def roof(
    image: np.ndarray,
    bottom_left: tuple[int, int],
    fill: tuple[int, int, int] = (150, 80, 40),
    tiles: tuple[int, int, int] = (90, 45, 20),
) -> None:
    """Draw a brown roof (60 px wide, 30 px high, with tiles) standing on (x, y); ``fill`` and
    ``tiles`` are its RGB colours."""
    x, y = bottom_left
    triangle = np.array([[x, y], [x + BODY_SIZE - 1, y], [x + BODY_SIZE // 2, y - 30]], np.int32)
    cv2.fillConvexPoly(image, triangle, fill)
    for k in range(1, 4):
        yy = y - 7 * k
        half = int(round((BODY_SIZE / 2) * (1 - 7 * k / 30)))
        cv2.line(image, (x + BODY_SIZE // 2 - half, yy), (x + BODY_SIZE // 2 + half, yy), tiles, 2)
    cv2.polylines(image, [triangle], True, tiles, 2)


def houses_world(
    bodies: list[tuple[int, int]],
    roofs_on: list[int],
    loose_roofs: Sequence[tuple[int, int]] = (),
    size: tuple[int, int] = (480, 360),
    seed: int = 0,
) -> np.ndarray:
    """The house-and-roof world (H, W, 3) uint8 RGB on a lightly textured board: house bodies
    with their top-left corners at ``bodies``, a roof on top of the bodies indexed by
    ``roofs_on``, and roofs lying at ``loose_roofs`` (bottom-left corners)."""
    image = board(size, seed)
    for x, y in bodies:
        house_body(image, (x, y))
    for index in roofs_on:
        x, y = bodies[index]
        roof(image, (x, y - 1))
    for corner in loose_roofs:
        roof(image, corner)
    return image


def board(size: tuple[int, int] = (480, 360), seed: int = 0) -> np.ndarray:
    """The empty house-and-roof workspace (H, W, 3) uint8 RGB of ``size`` (W, H): a light grey
    board with a faint smooth texture (seeded)."""
    width, height = size
    rng = np.random.default_rng(seed)
    surface = np.full((height, width, 3), 225, np.float32) + rng.normal(0, 3.0, (height, width, 1))
    return np.clip(cv2.GaussianBlur(surface, (0, 0), 2.0), 0, 255).astype(np.uint8)


# -- sprites: objects composited at any pose ----------------------------------------------------
# Poses are (x, y, angle): the sprite's anchor at (x, y) px (continuous coordinates, pixel i
# covering [i, i + 1)) and the sprite turned by ``angle`` (rad, image coordinates: positive
# turns x towards y, clockwise on screen), as the match decomposition measures θ.
_SPRITE_MARGIN = 4


@dataclass(frozen=True, eq=False)
class Sprite:
    """An object's picture: ``colour`` (h, w, 3) uint8 RGB, ``alpha`` (h, w) float32 in [0, 1],
    and its ``anchor`` (x, y), the point of the patch (continuous px) a pose puts in place."""

    colour: np.ndarray
    alpha: np.ndarray
    anchor: tuple[float, float]


def _sprite(draw, shape: tuple[int, int], anchor: tuple[float, float]) -> Sprite:
    """A sprite from a drawing function ``draw(image)`` on a patch of ``shape`` (h, w): the
    pixels it paints alike on a black and on a white patch are the object's."""
    dark, light = np.zeros((*shape, 3), np.uint8), np.full((*shape, 3), 255, np.uint8)
    draw(dark)
    draw(light)
    alpha = np.all(dark == light, axis=2).astype(np.float32)
    return Sprite(dark, alpha, anchor)


def body_sprite() -> Sprite:
    """A house body (:func:`house_body`, 60×60 px) anchored at its centre."""
    m = _SPRITE_MARGIN
    return _sprite(
        lambda image: house_body(image, (m, m)), (BODY_SIZE + 2 * m,) * 2, (m + BODY_SIZE / 2, m + BODY_SIZE / 2)
    )


ROOF_HEIGHT = 31  # px, rows a roof covers
ROOF_ANCHOR_ABOVE_BASE = 10.0  # px, the roof's anchor (near its centroid) above its base edge


ROOF_PAINT = ((195, 100, 30), (125, 60, 15))  # a roof's fill and tiles: orange-brown, named "orange"


def roof_sprite() -> Sprite:
    """A roof (:func:`roof` in :data:`ROOF_PAINT`, 60 px wide, 31 rows high) anchored on its
    axis, 10 px above its base edge (near the triangle's centroid)."""
    m = _SPRITE_MARGIN
    return _sprite(
        lambda image: roof(image, (m, m + ROOF_HEIGHT - 1), *ROOF_PAINT),
        (ROOF_HEIGHT + 2 * m, BODY_SIZE + 2 * m),
        (m + BODY_SIZE / 2, m + ROOF_HEIGHT - ROOF_ANCHOR_ABOVE_BASE),
    )


def sprite_transform(sprite: Sprite, pose: tuple[float, float, float]) -> np.ndarray:
    """The affine map (2, 3) from the sprite's pixel indices to the image's at ``pose``."""
    x, y, angle = pose
    c, s = np.cos(angle), np.sin(angle)
    rotation = np.array([[c, -s], [s, c]])
    shift = rotation @ (0.5 - np.asarray(sprite.anchor)) + np.array([x, y]) - 0.5
    return np.column_stack([rotation, shift])


def paste(image: np.ndarray, sprite: Sprite, pose: tuple[float, float, float]) -> None:
    """Composite ``sprite`` into ``image`` (H, W, 3) uint8 in place at ``pose`` (x, y, angle),
    blending its anti-aliased edge."""
    height, width = image.shape[:2]
    matrix = sprite_transform(sprite, pose)
    corners = np.array(
        [
            [0, 0],
            [sprite.alpha.shape[1], 0],
            [0, sprite.alpha.shape[0]],
            [sprite.alpha.shape[1], sprite.alpha.shape[0]],
        ],
        float,
    )
    placed = corners @ matrix[:, :2].T + matrix[:, 2]
    x0, y0 = np.maximum(np.floor(placed.min(axis=0)).astype(int) - 1, 0)
    x1, y1 = np.minimum(np.ceil(placed.max(axis=0)).astype(int) + 2, (width, height))
    if x1 <= x0 or y1 <= y0:
        return
    local = matrix.copy()
    local[:, 2] -= (x0, y0)
    size = (int(x1 - x0), int(y1 - y0))
    colour = cv2.warpAffine(sprite.colour, local, size, flags=cv2.INTER_LINEAR).astype(np.float32)
    alpha = cv2.warpAffine(sprite.alpha, local, size, flags=cv2.INTER_LINEAR)[:, :, None]
    region = image[y0:y1, x0:x1].astype(np.float32)
    image[y0:y1, x0:x1] = np.clip(np.round(alpha * colour + (1.0 - alpha) * region), 0, 255).astype(np.uint8)


def covers(sprite: Sprite, pose: tuple[float, float, float], point: tuple[float, float]) -> bool:
    """Whether the sprite at ``pose`` covers the image ``point`` (x, y) px."""
    matrix = sprite_transform(sprite, pose)
    inside = np.linalg.solve(matrix[:, :2], np.asarray(point, float) - 0.5 - matrix[:, 2])
    col, row = int(np.floor(inside[0] + 0.5)), int(np.floor(inside[1] + 0.5))
    return 0 <= row < sprite.alpha.shape[0] and 0 <= col < sprite.alpha.shape[1] and sprite.alpha[row, col] > 0.5
