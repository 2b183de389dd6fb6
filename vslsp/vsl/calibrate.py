"""A camera's ``calibration.json`` (docs/recordings.md) computed from pictures, for
:mod:`vslsp.vsl.calibration` to read: from a checkerboard lying on the table (OpenCV's
``findChessboardCorners`` and ``cornerSubPix``; ``calibrateCamera`` for the camera matrix K and
the lens distortion, ``solvePnP`` for the table plane) or from four (or more) table points
marked in one picture (``findHomography``: image pixels to table metres).

The table frame of a checkerboard calibration is the board's, as it lies in the last picture:
its origin at the first inner corner OpenCV finds, x along that corner's row, z up from the
table toward the camera (the board's own z turned over when it points into the table, and y
with it: then the corner of column i and row j is at (i s, -j s, 0) for squares of side s).
"""

from __future__ import annotations

import re
from collections.abc import Sequence

import cv2
import numpy as np

from vslsp.errors import InputError

_SUBPIX = (cv2.TERM_CRITERIA_EPS + cv2.TERM_CRITERIA_MAX_ITER, 50, 1e-4)
_PAIR = re.compile(r"^\s*([-+0-9.eE]+),([-+0-9.eE]+):([-+0-9.eE]+),([-+0-9.eE]+)\s*$")


def parse_pattern(text: str) -> tuple[int, int]:
    """``COLSxROWS`` (the board's inner corners, e.g. ``9x6``) as (cols, rows)."""
    match = re.fullmatch(r"\s*(\d+)\s*[xX]\s*(\d+)\s*", text)
    if match is None or min(int(match.group(1)), int(match.group(2))) < 2:
        raise InputError(f"--checkerboard {text}: give the inner corners as COLSxROWS, e.g. 9x6 (each at least 2)")
    return int(match.group(1)), int(match.group(2))


def parse_points(texts: Sequence[str]) -> tuple[np.ndarray, np.ndarray]:
    """Pairs ``u,v:x,y`` (image pixels : table metres) as (N, 2) pixels and (N, 2) metres."""
    pixels, table = [], []
    for text in texts:
        match = _PAIR.match(text)
        if match is None:
            raise InputError(f"--points {text}: give each point as u,v:x,y (image pixels : table metres)")
        u, v, x, y = (float(c) for c in match.groups())
        pixels.append((u, v))
        table.append((x, y))
    if len(pixels) < 4:
        raise InputError(f"--points: give at least four u,v:x,y pairs (got {len(pixels)})")
    return np.array(pixels), np.array(table)


def find_corners(image: np.ndarray, pattern: tuple[int, int], name: str) -> np.ndarray:
    """The board's inner corners (cols * rows, 2) px in ``image`` (H, W, 3), refined to
    sub-pixel; InputError naming ``name`` when the board is not found."""
    gray = cv2.cvtColor(image, cv2.COLOR_RGB2GRAY)
    flags = cv2.CALIB_CB_ADAPTIVE_THRESH + cv2.CALIB_CB_NORMALIZE_IMAGE
    found, corners = cv2.findChessboardCorners(gray, pattern, flags=flags)
    if not found:
        raise InputError(
            f"{name}: no checkerboard of {pattern[0]}x{pattern[1]} inner corners found; "
            "check --checkerboard and that the whole board is in view"
        )
    corners = cv2.cornerSubPix(gray, corners, (5, 5), (-1, -1), _SUBPIX)
    return corners.reshape(-1, 2).astype(np.float64)


def board_points(pattern: tuple[int, int], square_m: float) -> np.ndarray:
    """The inner corners (cols * rows, 3) in the board's frame (m), OpenCV's order."""
    cols, rows = pattern
    grid = np.mgrid[0:cols, 0:rows].T.reshape(-1, 2) * square_m
    return np.hstack([grid, np.zeros((len(grid), 1))])


def checkerboard_calibration(
    images: Sequence[np.ndarray], names: Sequence[str], pattern: tuple[int, int], square_m: float
) -> dict:
    """``calibration.json`` from pictures (H, W, 3) of a checkerboard of ``pattern`` inner
    corners and ``square_m`` squares: with two or more pictures ``calibrateCamera`` gives K and
    the distortion (k1, k2, p1, p2; k3 = 0); from one picture, K has its focal length fitted with
    the principal point at the centre and no distortion. The table plane is the board's in the
    last picture. ``rms_px``: the reprojection error."""
    if not square_m > 0:
        raise InputError("--square: give the side of a square in millimetres (> 0)")
    height, width = images[0].shape[:2]
    for image, name in zip(images, names):
        if image.shape[:2] != (height, width):
            raise InputError(f"{name} is {image.shape[1]}x{image.shape[0]} px, {names[0]} {width}x{height}")
    corners = [find_corners(image, pattern, name).astype(np.float32) for image, name in zip(images, names)]
    board = board_points(pattern, square_m).astype(np.float32)
    size = (width, height)
    if len(images) >= 2:
        flags = cv2.CALIB_FIX_K3  # k3 is for wide lenses; a board in the middle of the view cannot fix it
        guess = None
    else:  # one view does not fix the principal point and the distortion: keep them nominal
        flags = (
            cv2.CALIB_FIX_PRINCIPAL_POINT
            | cv2.CALIB_FIX_ASPECT_RATIO
            | cv2.CALIB_ZERO_TANGENT_DIST
            | cv2.CALIB_FIX_K1
            | cv2.CALIB_FIX_K2
            | cv2.CALIB_FIX_K3
            | cv2.CALIB_USE_INTRINSIC_GUESS
        )
        focal = float(max(width, height))
        guess = np.array([[focal, 0.0, width / 2.0], [0.0, focal, height / 2.0], [0.0, 0.0, 1.0]])
    rms, matrix, distortion, rvecs, tvecs = cv2.calibrateCamera(
        [board] * len(corners), corners, size, guess, None, flags=flags
    )
    rotation = cv2.Rodrigues(rvecs[-1])[0]
    translation = np.asarray(tvecs[-1], np.float64).reshape(3)
    # The board's z points into the table when the camera sees its corners' rows turn clockwise
    # into its columns; the table frame's z points up, toward the camera: turn it over about x.
    if (-rotation.T @ translation)[2] < 0:
        rotation = rotation @ np.diag([1.0, -1.0, -1.0])
    data = {
        "camera_matrix": np.asarray(matrix).tolist(),
        "rvec": cv2.Rodrigues(rotation)[0].reshape(3).tolist(),
        "translation": translation.tolist(),
        "image_size": [width, height],
        "rms_px": round(float(rms), 4),
    }
    if len(images) >= 2:
        data["distortion"] = np.asarray(distortion, np.float64).reshape(-1).tolist()
    return data


def points_calibration(pixels: np.ndarray, table: np.ndarray, size: tuple[int, int], name: str) -> dict:
    """``calibration.json`` of a homography from marked points: ``pixels`` (N, 2) of an image of
    ``size`` (W, H) and the table points (N, 2) m they see, N >= 4, no three in a line."""
    width, height = size
    outside = [(u, v) for u, v in pixels if not (0 <= u < width and 0 <= v < height)]
    if outside:
        raise InputError(f"{name}: the point {outside[0]} px is outside its {width}x{height} px")
    for points, what in ((pixels, "pixels"), (table, "table points")):
        if _collinear(points):
            raise InputError(f"--points: three of the {what} lie on one line; mark four corners of a table area")
    homography, _ = cv2.findHomography(pixels.astype(np.float64), table.astype(np.float64), 0)
    if homography is None or abs(np.linalg.det(homography)) < 1e-15:
        raise InputError("--points: no homography fits these points; mark them again")
    seen = cv2.perspectiveTransform(pixels.reshape(-1, 1, 2).astype(np.float64), homography).reshape(-1, 2)
    return {
        "homography": (homography / homography[2, 2]).tolist(),
        "image_size": [width, height],
        "rms_m": round(float(np.sqrt(np.mean(np.sum((seen - table) ** 2, axis=1)))), 6),
    }


def _collinear(points: np.ndarray) -> bool:
    scale = float(np.ptp(points, axis=0).max()) or 1.0
    for i in range(len(points)):
        for j in range(i + 1, len(points)):
            for k in range(j + 1, len(points)):
                a, b = points[j] - points[i], points[k] - points[i]
                if abs(a[0] * b[1] - a[1] * b[0]) < 1e-6 * scale * scale:
                    return True
    return False
