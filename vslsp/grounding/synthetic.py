"""Synthetic tabletops drawn with OpenCV: a table with a black landmark line and shaded
coloured squares (paper, VSL-SP "Implementation": coloured cubes on a table with a black
borderline), part of the public grounding test kit (:mod:`vslsp.grounding.testkit`).

They give perception inputs whose truth is known exactly, without a simulator: tests and
benchmarks use them alongside rendered scenes.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

TABLE_RGB = (196, 181, 152)
PAINTS: dict[str, tuple[int, int, int]] = {
    "red": (215, 30, 30),
    "orange": (250, 130, 20),
    "yellow": (240, 215, 30),
    "green": (30, 175, 55),
    "blue": (30, 65, 225),
    "purple": (140, 40, 190),
    "grey": (128, 128, 128),
    "cyan": (20, 200, 200),
    "pink": (250, 160, 185),
}


@dataclass(frozen=True)
class Square:
    """A coloured square object: ``colour`` (a PAINTS name or an RGB triple), centre (x, y) px,
    side (px) and angle (deg, image coordinates)."""

    colour: str | tuple[int, int, int]
    centre: tuple[float, float]
    side: float = 60.0
    angle: float = 0.0


def tabletop_image(
    squares: list[Square] | tuple[Square, ...],
    line: tuple[tuple[float, float], tuple[float, float]] | None = ((0.0, 300.0), (640.0, 260.0)),
    size: tuple[int, int] = (640, 480),
    line_width: int = 12,
    noise: float = 0.0,
    brightness: float = 1.0,
    seed: int = 0,
) -> np.ndarray:
    """An RGB (H, W, 3) uint8 tabletop of ``size`` (W, H): table colour with a slight gradient,
    the black ``line`` (two points it passes through), the squares shaded like lit cubes (a
    brighter top-left half, a darker bottom edge), Gaussian ``noise`` (sigma, grey levels) and
    a global ``brightness`` gain."""
    width, height = size
    rng = np.random.default_rng(seed)
    ramp = np.linspace(0.97, 1.03, width, dtype=np.float32)[None, :, None]
    image = np.broadcast_to(np.array(TABLE_RGB, np.float32), (height, width, 3)) * ramp
    if line is not None:
        (xa, ya), (xb, yb) = line
        d = np.array([xb - xa, yb - ya]) / np.hypot(xb - xa, yb - ya)
        far = 4.0 * (width + height)
        p, q = (xa - far * d[0], ya - far * d[1]), (xa + far * d[0], ya + far * d[1])
        cv2.line(image, _int(p), _int(q), (6.0, 6.0, 6.0), line_width, cv2.LINE_AA)
    for square in squares:
        _draw_square(image, square)
    image = image * brightness + rng.normal(0.0, noise, image.shape) if noise else image * brightness
    return np.clip(np.round(image), 0, 255).astype(np.uint8)


def _draw_square(image: np.ndarray, square: Square) -> None:
    colour = np.array(PAINTS[square.colour] if isinstance(square.colour, str) else square.colour, np.float32)
    corners = cv2.boxPoints((square.centre, (square.side, square.side), square.angle))
    mask = np.zeros(image.shape[:2], np.uint8)
    cv2.fillConvexPoly(mask, np.round(corners * 16).astype(np.int32), 1, cv2.LINE_8, shift=4)
    ys, xs = np.nonzero(mask)
    # Shading: lit towards the top-left, a darker side face along the bottom.
    along = ((xs - square.centre[0]) + (ys - square.centre[1])) / square.side
    shade = 1.0 - 0.15 * np.clip(along, -1.0, 1.0)
    shade = np.where(ys - square.centre[1] > 0.3 * square.side, shade * 0.7, shade)
    image[ys, xs] = np.clip(colour[None, :] * shade[:, None], 0, 255)


def _int(point) -> tuple[int, int]:
    return int(round(point[0])), int(round(point[1]))
