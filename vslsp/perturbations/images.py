"""The image side of a perturbation: other light, sensor noise and compression on an RGB image,
noise and holes on a depth image, part of an object hidden. Each operation is a pure function of
its image and its draw; :func:`apply` runs the light and the noise of a trial's draw in the order
a camera meets them (the scene's light, then the sensor's noise, then the encoder).
"""

from __future__ import annotations

import cv2
import numpy as np

from vslsp.perturbations.spec import Drawn

#: The colour temperature (K) of the light the demonstrations were rendered under.
NEUTRAL_K = 6500.0
#: Luma weights (ITU-R BT.601): a colour temperature's channel gains keep this weighted mean at 1.
LUMA = np.array([0.299, 0.587, 0.114])


def apply(image: np.ndarray, drawn: Drawn, index: int) -> np.ndarray:
    """``image`` (H, W, 3) uint8 RGB under ``drawn``'s light and noise; its ``index``-th image of the
    trial draws its own noise. The image itself when the draw changes no image."""
    if not drawn.photometric:
        return image
    levels = drawn.levels
    out = image.astype(np.float32)
    if levels.temperature != NEUTRAL_K:
        out *= temperature_gains(levels.temperature)
    if levels.contrast:
        mean = out.mean(axis=(0, 1), keepdims=True)
        out = (out - mean) * drawn.contrast + mean
    if levels.brightness:
        out *= drawn.brightness
    if levels.shadow:
        out *= shadow_band(out.shape[:2], levels.shadow, *drawn.shadow)[..., None]
    rng = drawn.noise_rng(index)
    if levels.noise:
        out += rng.normal(0.0, levels.noise, size=out.shape).astype(np.float32)
    result = np.clip(np.rint(out), 0, 255).astype(np.uint8)
    if levels.salt:
        result = salt_and_pepper(result, levels.salt, rng)
    if levels.jpeg:
        result = jpeg(result, int(round(levels.jpeg)))
    return result


def temperature_gains(kelvin: float) -> np.ndarray:
    """Per-channel (R, G, B) gains that turn daylight (:data:`NEUTRAL_K`) into light of ``kelvin``:
    the ratio of the two black bodies' colours (Helland's fit of the Planckian locus in sRGB),
    scaled so that the image's luma stays (only its colour changes)."""
    gains = _blackbody_rgb(kelvin) / _blackbody_rgb(NEUTRAL_K)
    return (gains / float(LUMA @ gains)).astype(np.float32)


def _blackbody_rgb(kelvin: float) -> np.ndarray:
    t = kelvin / 100.0
    red = 255.0 if t <= 66 else 329.698727446 * (t - 60) ** -0.1332047592
    green = 99.4708025861 * np.log(t) - 161.1195681661 if t <= 66 else 288.1221695283 * (t - 60) ** -0.0755148492
    blue = 255.0 if t >= 66 else (0.0 if t <= 19 else 138.5177312231 * np.log(t - 10) - 305.0447927307)
    return np.clip(np.array([red, green, blue], dtype=float), 1.0, 255.0)


def shadow_band(shape: tuple[int, int], strength: float, angle: float, offset: float) -> np.ndarray:
    """(H, W) float32 light factors of a soft shadow band: a band a fifth of the view's diagonal
    wide, along direction ``angle`` (rad), its centre line ``offset`` diagonals off the view's
    centre, darkened by ``strength`` at its middle and fading to none over its outer halves."""
    height, width = shape
    diagonal = float(np.hypot(height, width))
    v, u = np.mgrid[0:height, 0:width].astype(np.float32)
    normal = np.array([-np.sin(angle), np.cos(angle)], dtype=np.float32)
    distance = (u - width / 2.0) * normal[0] + (v - height / 2.0) * normal[1] - offset * diagonal
    half = 0.1 * diagonal
    inside = np.clip((half - np.abs(distance)) / (0.5 * half), 0.0, 1.0)
    smooth = inside * inside * (3.0 - 2.0 * inside)
    return (1.0 - strength * smooth).astype(np.float32)


def salt_and_pepper(image: np.ndarray, share: float, rng: np.random.Generator) -> np.ndarray:
    """``image`` with ``share`` of its pixels set black or white (half each, drawn by ``rng``)."""
    out = image.copy()
    hit = rng.random(image.shape[:2]) < share
    white = rng.random(image.shape[:2]) < 0.5
    out[hit & white] = 255
    out[hit & ~white] = 0
    return out


def jpeg(image: np.ndarray, quality: int) -> np.ndarray:
    """``image`` (RGB) encoded as JPEG at ``quality`` (1-100) and decoded again."""
    ok, data = cv2.imencode(".jpg", cv2.cvtColor(image, cv2.COLOR_RGB2BGR), [cv2.IMWRITE_JPEG_QUALITY, quality])
    assert ok  # OpenCV encodes any uint8 RGB image
    return cv2.cvtColor(cv2.imdecode(data, cv2.IMREAD_COLOR), cv2.COLOR_BGR2RGB)


def depth_noise(depth: np.ndarray, sigma_m: float, rng: np.random.Generator) -> np.ndarray:
    """``depth`` (m) with Gaussian noise of ``sigma_m`` on its valid (finite, positive) pixels."""
    out = depth.astype(np.float32, copy=True)
    valid = np.isfinite(out) & (out > 0)
    out[valid] += rng.normal(0.0, sigma_m, size=int(valid.sum())).astype(np.float32)
    return out


def depth_holes(depth: np.ndarray, share: float, rng: np.random.Generator, missing: float = 0.0) -> np.ndarray:
    """``depth`` with ``share`` of its pixels lost (set to ``missing``, the sensor's no-return),
    in small blobs as a structured-light sensor loses them (3x3 px each)."""
    height, width = depth.shape
    seeds = rng.random((height, width)) < share / 9.0
    lost = cv2.dilate(seeds.astype(np.uint8), np.ones((3, 3), np.uint8)).astype(bool)
    out = depth.astype(np.float32, copy=True)
    out[lost] = missing
    return out


def occlude(
    image: np.ndarray, box: tuple[float, float, float, float], share: float, side: float, rng: np.random.Generator
) -> np.ndarray:
    """``image`` with ``share`` of the box ``(x0, y0, x1, y1)`` px hidden by a grey occluder (an arm,
    another object) that comes from direction ``side`` (rad): the pixels of the box farthest that
    way, ``share`` of its area, are covered with a mid-grey of faint texture."""
    x0, y0, x1, y1 = (int(round(v)) for v in box)
    height, width = image.shape[:2]
    x0, x1, y0, y1 = max(0, x0), min(width, x1), max(0, y0), min(height, y1)
    if x1 <= x0 or y1 <= y0 or share <= 0:
        return image
    v, u = np.mgrid[y0:y1, x0:x1].astype(np.float32)
    reach = u * np.cos(side) + v * np.sin(side)
    covered = reach >= np.quantile(reach, 1.0 - share)
    out = image.copy()
    texture = 128.0 + rng.normal(0.0, 6.0, size=(int(covered.sum()), 1))
    out[y0:y1, x0:x1][covered] = np.clip(texture, 0, 255).astype(np.uint8)
    return out
