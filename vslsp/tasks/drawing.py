"""Drawing helpers shared by the reports' pictures (RGB images, OpenCV)."""

from __future__ import annotations

import cv2
import numpy as np

PICK, PLACE = (255, 0, 255), (0, 170, 255)  # RGB: the pick frame (magenta), the place frame (azure)
SCALE = 0.5  # pictures at half the camera's resolution


def small(image: np.ndarray, scale: float = SCALE) -> np.ndarray:
    """``image`` (H, W, 3) shrunk by ``scale``."""
    return cv2.resize(image, None, fx=scale, fy=scale, interpolation=cv2.INTER_AREA)


def label(image: np.ndarray, text: str, origin: tuple[int, int] = (8, 26)) -> np.ndarray:
    """A copy of ``image`` with ``text`` in white on a dark band, readable on any background;
    a text wider than the picture goes on as many lines as it needs (broken between words)."""
    image = image.copy()
    x, y = origin
    for line in _lines(text, image.shape[1] - x - 6):
        (width, height), baseline = cv2.getTextSize(line, cv2.FONT_HERSHEY_SIMPLEX, 0.6, 2)
        top, bottom = max(0, y - height - 6), min(image.shape[0], y + baseline + 4)
        band = image[top:bottom, max(0, x - 6) : min(image.shape[1], x + width + 6)]
        band[:] = (0.25 * band).astype(image.dtype)
        cv2.putText(image, line, (x, y), cv2.FONT_HERSHEY_SIMPLEX, 0.6, (255, 255, 255), 2, cv2.LINE_AA)
        y += height + baseline + 10
    return image


def _lines(text: str, width: int) -> list[str]:
    """``text`` broken between words into lines at most ``width`` px wide as :func:`label`
    draws them (a single word wider than that keeps a line of its own)."""
    lines: list[str] = []
    for word in text.split(" "):
        joined = f"{lines[-1]} {word}" if lines else word
        if lines and cv2.getTextSize(joined, cv2.FONT_HERSHEY_SIMPLEX, 0.6, 2)[0][0] <= width:
            lines[-1] = joined
        else:
            lines.append(word)
    return lines or [""]


def legend(width: int, entries: list[tuple[str, tuple[int, int, int], str]]) -> np.ndarray:
    """A strip ``width`` px wide (H, width, 3) that explains a picture's marks: per entry its mark
    (``"square"``, ``"arrow"`` or ``"cross"``) in its colour, then its words; entries go on as many
    rows as they need."""
    rows: list[list[tuple[str, tuple[int, int, int], str]]] = [[]]
    used = 8
    for entry in entries:
        needed = 36 + cv2.getTextSize(entry[2], cv2.FONT_HERSHEY_SIMPLEX, 0.5, 1)[0][0] + 20
        if rows[-1] and used + needed > width:
            rows.append([])
            used = 8
        rows[-1].append(entry)
        used += needed
    strip = np.full((10 + 26 * len(rows), width, 3), 250, np.uint8)
    for r, row in enumerate(rows):
        x, y = 8, 22 + 26 * r
        for mark, colour, words in row:
            if mark == "square":
                cv2.rectangle(strip, (x, y - 12), (x + 18, y + 4), colour, 2)
            elif mark == "arrow":
                cv2.arrowedLine(strip, (x, y - 4), (x + 24, y - 4), colour, 2, cv2.LINE_AA, tipLength=0.35)
            else:
                cv2.drawMarker(strip, (x + 9, y - 4), colour, cv2.MARKER_CROSS, 16, 2)
            cv2.putText(strip, words, (x + 32, y), cv2.FONT_HERSHEY_SIMPLEX, 0.5, (20, 20, 20), 1, cv2.LINE_AA)
            x += 36 + cv2.getTextSize(words, cv2.FONT_HERSHEY_SIMPLEX, 0.5, 1)[0][0] + 20
    return strip


def with_legend(picture: np.ndarray, entries: list[tuple[str, tuple[int, int, int], str]]) -> np.ndarray:
    """``picture`` with its :func:`legend` below it."""
    return np.vstack([picture, legend(picture.shape[1], entries)])


def square(image: np.ndarray, centre: tuple[float, float], size: float, colour: tuple[int, int, int]) -> None:
    """Draw an axis-aligned square frame of side ``size`` px about ``centre`` (in place)."""
    half = size / 2.0
    cv2.rectangle(
        image, point((centre[0] - half, centre[1] - half)), point((centre[0] + half, centre[1] + half)), colour, 3
    )


def point(xy) -> tuple[int, int]:
    """Pixel coordinates rounded for OpenCV."""
    return int(round(xy[0])), int(round(xy[1]))


def grid(panels: list[np.ndarray], columns: int) -> np.ndarray:
    """Panels of one size in rows of ``columns`` (the last row padded with black)."""
    rows = []
    for i in range(0, len(panels), columns):
        row = panels[i : i + columns]
        rows.append(np.hstack(row + [np.zeros_like(panels[0])] * (columns - len(row))))
    return np.vstack(rows)


def caption(image: np.ndarray, lines: list[str], scale: float | None = None) -> np.ndarray:
    """``image`` (H, W, 3) under a dark band with ``lines`` of white text, wrapped to its width
    (H + band, W, 3): the words say what the picture shows, without covering any of it."""
    scale = scale or max(0.5, image.shape[1] / 1600)
    thickness = max(1, int(round(2 * scale)))
    margin = int(10 * scale)
    wrapped = [text for line in lines for text in _wrap(line, image.shape[1] - 2 * margin, scale, thickness)]
    step = int(34 * scale)
    band = np.full((step * len(wrapped) + int(12 * scale), image.shape[1], 3), 30, np.uint8)
    for k, text in enumerate(wrapped):
        cv2.putText(
            band,
            text,
            (margin, step * (k + 1)),
            cv2.FONT_HERSHEY_SIMPLEX,
            scale,
            (255, 255, 255),
            thickness,
            cv2.LINE_AA,
        )
    return np.vstack([band, image])


def _wrap(text: str, width: int, scale: float, thickness: int) -> list[str]:
    """``text`` in lines no wider than ``width`` px (a single word wider than that stays whole)."""
    lines: list[str] = []
    for word in text.split(" "):
        trial = f"{lines[-1]} {word}" if lines else word
        if lines and cv2.getTextSize(trial, cv2.FONT_HERSHEY_SIMPLEX, scale, thickness)[0][0] <= width:
            lines[-1] = trial
        else:
            lines.append(word)
    return lines
