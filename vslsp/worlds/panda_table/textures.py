"""Procedural textures for the real-world VSL tasks (paper, "Real-world Experiments", Table 1):
letter tiles A-D, frog and giraffe puzzle pieces, pictures of animals and machines, picture
domino pieces, Tower-of-Hanoi disks, and the landmarks the robot detects but never moves (a
right-angle ruler baseline, 'pond' and 'tree' labels, two labelled bins, three Hanoi bases).

VSL knows nothing about the objects a priori; it finds them again with SIFT (Lowe 2004), so
every texture is busy at the scale the camera sees it (a 6 cm tile is about a hundred pixels
wide): a background of seeded confetti (small discs, triangles, strokes of many colours) that
is unique per texture, under the picture that tells a person what the object is. Everything
is drawn with OpenCV from a seed derived from the texture's name: the same call gives the same
pixels. Each texture is (H, W, 3) uint8 RGB at :data:`PX_PER_M`, its width along the item's
x size (the top face as the world lays it out).
"""

from __future__ import annotations

import zlib

import cv2
import numpy as np

PX_PER_M = 2400  # texture resolution: 2.4 px per mm
_FONT = cv2.FONT_HERSHEY_DUPLEX
_PALETTE = np.array(
    [
        (220, 40, 40),
        (30, 150, 60),
        (40, 70, 220),
        (240, 190, 20),
        (150, 50, 180),
        (20, 170, 190),
        (245, 120, 30),
        (60, 60, 60),
        (250, 250, 250),
        (120, 80, 40),
    ],
    np.uint8,
)


def _seed(name: str) -> int:
    return zlib.crc32(name.encode("utf-8"))


def _canvas(
    size: tuple[float, float],
    name: str,
    background: tuple[int, int, int],
    density: float = 1.0,
    border: tuple[int, int, int] | None = (40, 40, 40),
) -> np.ndarray:
    """A (H, W, 3) canvas for an item of ``size`` (x, y) m: ``background`` with seeded confetti
    (``density`` shapes per cm²) and a border line."""
    width, height = max(32, int(round(size[0] * PX_PER_M))), max(32, int(round(size[1] * PX_PER_M)))
    rng = np.random.default_rng(_seed(name))
    image = np.empty((height, width, 3), np.uint8)
    image[:] = background
    count = int(density * size[0] * size[1] * 1e4)
    for _ in range(count):
        colour = tuple(int(c) for c in _PALETTE[rng.integers(len(_PALETTE))])
        x, y = int(rng.integers(width)), int(rng.integers(height))
        r = int(rng.integers(6, 16))
        kind = rng.integers(3)
        if kind == 0:
            cv2.circle(image, (x, y), r, colour, -1, cv2.LINE_AA)
        elif kind == 1:
            angle = rng.uniform(0, 2 * np.pi)
            points = [(x + r * 1.6 * np.cos(angle + a), y + r * 1.6 * np.sin(angle + a)) for a in (0, 2.2, 4.0)]
            cv2.fillPoly(image, [np.round(points).astype(np.int32)], colour, cv2.LINE_AA)
        else:
            angle = rng.uniform(0, np.pi)
            dx, dy = 2.2 * r * np.cos(angle), 2.2 * r * np.sin(angle)
            cv2.line(image, (int(x - dx), int(y - dy)), (int(x + dx), int(y + dy)), colour, 5, cv2.LINE_AA)
    if border is not None:
        thickness = max(4, min(width, height) // 30)
        cv2.rectangle(image, (0, 0), (width - 1, height - 1), border, thickness)
    return image


def _text(
    image: np.ndarray,
    text: str,
    centre: tuple[float, float],
    height: float,
    colour=(20, 20, 20),
    outline=(255, 255, 255),
    angle: float = 0.0,
) -> None:
    """Draw ``text`` about ``centre`` (px), ``height`` px tall, outlined, turned by ``angle`` deg."""
    scale = height / 22.0
    thickness = max(2, int(round(height / 9)))
    (w, h), _ = cv2.getTextSize(text, _FONT, scale, thickness)
    pad = 2 * thickness
    patch = np.zeros((h + 2 * pad + 4, w + 2 * pad, 3), np.uint8)
    mask = np.zeros(patch.shape[:2], np.uint8)
    origin = (pad, h + pad)
    cv2.putText(mask, text, origin, _FONT, scale, 255, thickness + 2 * max(2, thickness // 2), cv2.LINE_AA)
    cv2.putText(patch, text, origin, _FONT, scale, outline, thickness + 2 * max(2, thickness // 2), cv2.LINE_AA)
    cv2.putText(patch, text, origin, _FONT, scale, colour, thickness, cv2.LINE_AA)
    turn = cv2.getRotationMatrix2D((patch.shape[1] / 2.0, patch.shape[0] / 2.0), angle, 1.0)
    turn[:, 2] += (centre[0] - patch.shape[1] / 2.0, centre[1] - patch.shape[0] / 2.0)
    shape = (image.shape[1], image.shape[0])
    drawn = cv2.warpAffine(patch, turn, shape)
    alpha = cv2.warpAffine(mask, turn, shape).astype(np.float32)[..., None] / 255.0
    image[:] = (image * (1.0 - alpha) + drawn * alpha).astype(np.uint8)


def letter_tile(letter: str, size: tuple[float, float] = (0.05, 0.05)) -> np.ndarray:
    """A tile with a big ``letter`` (A-D in the alphabet task) over confetti."""
    image = _canvas(size, f"letter-{letter}", (235, 225, 200), density=0.8)
    h, w = image.shape[:2]
    _text(image, letter, (w / 2.0, h / 2.0), 0.62 * h, colour=(30, 30, 140))
    return image


def _frog(image: np.ndarray) -> None:
    h, w = image.shape[:2]
    green, dark = (40, 160, 60), (20, 80, 30)
    cv2.ellipse(image, (w // 2, int(h * 0.58)), (int(w * 0.32), int(h * 0.3)), 0, 0, 360, green, -1, cv2.LINE_AA)
    for side in (-1, 1):
        cv2.ellipse(
            image,
            (w // 2 + side * int(w * 0.3), int(h * 0.78)),
            (int(w * 0.14), int(h * 0.1)),
            side * 30,
            0,
            360,
            dark,
            -1,
            cv2.LINE_AA,
        )
        eye = (w // 2 + side * int(w * 0.14), int(h * 0.3))
        cv2.circle(image, eye, int(h * 0.09), (250, 250, 250), -1, cv2.LINE_AA)
        cv2.circle(image, eye, int(h * 0.04), (10, 10, 10), -1, cv2.LINE_AA)
    cv2.ellipse(image, (w // 2, int(h * 0.5)), (int(w * 0.16), int(h * 0.06)), 0, 0, 180, (200, 40, 40), 6, cv2.LINE_AA)


def _giraffe(image: np.ndarray, seed: int) -> None:
    h, w = image.shape[:2]
    yellow, brown = (235, 190, 60), (140, 80, 30)
    body = np.array([(0.2, 0.62), (0.75, 0.6), (0.8, 0.8), (0.2, 0.82)]) * (w, h)
    neck = np.array([(0.62, 0.62), (0.74, 0.6), (0.62, 0.15), (0.55, 0.17)]) * (w, h)
    cv2.fillPoly(image, [body.astype(np.int32), neck.astype(np.int32)], yellow, cv2.LINE_AA)
    cv2.ellipse(
        image, (int(w * 0.6), int(h * 0.14)), (int(w * 0.09), int(h * 0.05)), -20, 0, 360, yellow, -1, cv2.LINE_AA
    )
    for x in (0.25, 0.35, 0.65, 0.75):
        cv2.line(image, (int(w * x), int(h * 0.8)), (int(w * x), int(h * 0.95)), yellow, 10, cv2.LINE_AA)
    rng = np.random.default_rng(seed)
    for _ in range(22):
        point = body[0] + rng.uniform(0.05, 0.95) * (body[1] - body[0]) + rng.uniform(0.1, 0.9) * (body[3] - body[0])
        cv2.circle(image, (int(point[0]), int(point[1])), int(rng.integers(5, 11)), brown, -1, cv2.LINE_AA)
    for t in np.linspace(0.1, 0.9, 6):
        point = neck[0] + t * (neck[3] - neck[0]) + 0.5 * (neck[1] - neck[0])
        cv2.circle(image, (int(point[0]), int(point[1])), 6, brown, -1, cv2.LINE_AA)


def puzzle_piece(animal: str, part: int, size: tuple[float, float] = (0.05, 0.05)) -> np.ndarray:
    """Piece ``part`` (0 left, 1 right) of the ``animal`` ("frog" or "giraffe") puzzle: the
    animal is drawn across two tiles side by side; each piece is one half."""
    if animal not in ("frog", "giraffe") or part not in (0, 1):
        raise ValueError(f"no puzzle piece {animal!r} {part!r}; animals: frog, giraffe; parts: 0, 1")
    whole = _canvas(
        (2 * size[0], size[1]),
        f"puzzle-{animal}",
        (190, 225, 245) if animal == "frog" else (215, 240, 200),
        density=0.5,
        border=None,
    )
    _frog(whole) if animal == "frog" else _giraffe(whole, _seed(animal))
    half = whole.shape[1] // 2
    piece = np.ascontiguousarray(whole[:, part * half : (part + 1) * half])
    cv2.rectangle(piece, (0, 0), (piece.shape[1] - 1, piece.shape[0] - 1), (40, 40, 40), 4)
    return piece


def _drawing(image: np.ndarray, subject: str) -> None:
    """A simple drawing of ``subject`` in the middle of ``image``."""
    h, w = image.shape[:2]
    c, s = (w // 2, int(h * 0.45)), min(w, h)
    if subject == "cat":
        cv2.circle(image, c, int(s * 0.25), (240, 140, 40), -1, cv2.LINE_AA)
        for side in (-1, 1):
            ear = np.array(
                [
                    (c[0] + side * s * 0.22, c[1] - s * 0.1),
                    (c[0] + side * s * 0.08, c[1] - s * 0.2),
                    (c[0] + side * s * 0.22, c[1] - s * 0.36),
                ],
                np.int32,
            )
            cv2.fillPoly(image, [ear], (240, 140, 40), cv2.LINE_AA)
            cv2.circle(image, (c[0] + side * int(s * 0.1), c[1] - int(s * 0.05)), int(s * 0.04), (20, 90, 20), -1)
            cv2.line(
                image,
                (c[0] + side * int(s * 0.05), c[1] + int(s * 0.08)),
                (c[0] + side * int(s * 0.3), c[1] + int(s * 0.05)),
                (30, 30, 30),
                3,
                cv2.LINE_AA,
            )
    elif subject == "fish":
        cv2.ellipse(image, c, (int(s * 0.3), int(s * 0.15)), 0, 0, 360, (40, 120, 220), -1, cv2.LINE_AA)
        tail = np.array(
            [(c[0] + s * 0.26, c[1]), (c[0] + s * 0.42, c[1] - s * 0.14), (c[0] + s * 0.42, c[1] + s * 0.14)], np.int32
        )
        cv2.fillPoly(image, [tail], (220, 60, 60), cv2.LINE_AA)
        cv2.circle(image, (c[0] - int(s * 0.17), c[1] - int(s * 0.03)), int(s * 0.04), (255, 255, 255), -1)
        for k in range(3):
            cv2.ellipse(
                image,
                (c[0] - int(s * 0.05) + k * int(s * 0.09), c[1]),
                (int(s * 0.04), int(s * 0.1)),
                0,
                -60,
                60,
                (250, 220, 60),
                3,
                cv2.LINE_AA,
            )
    elif subject == "car":
        cv2.rectangle(
            image,
            (c[0] - int(s * 0.35), c[1] - int(s * 0.05)),
            (c[0] + int(s * 0.35), c[1] + int(s * 0.15)),
            (210, 30, 30),
            -1,
        )
        cv2.rectangle(
            image,
            (c[0] - int(s * 0.18), c[1] - int(s * 0.2)),
            (c[0] + int(s * 0.15), c[1] - int(s * 0.05)),
            (170, 210, 240),
            -1,
        )
        for side in (-1, 1):
            cv2.circle(image, (c[0] + side * int(s * 0.2), c[1] + int(s * 0.16)), int(s * 0.09), (20, 20, 20), -1)
            cv2.circle(image, (c[0] + side * int(s * 0.2), c[1] + int(s * 0.16)), int(s * 0.04), (200, 200, 200), -1)
    elif subject == "gear":
        for k in range(10):
            a = k * np.pi / 5
            tip = (int(c[0] + s * 0.32 * np.cos(a)), int(c[1] + s * 0.32 * np.sin(a)))
            cv2.line(image, c, tip, (90, 90, 110), int(s * 0.08), cv2.LINE_AA)
        cv2.circle(image, c, int(s * 0.25), (120, 120, 140), -1, cv2.LINE_AA)
        cv2.circle(image, c, int(s * 0.09), (240, 240, 240), -1, cv2.LINE_AA)
        cv2.rectangle(
            image,
            (c[0] - int(s * 0.02), c[1] - int(s * 0.12)),
            (c[0] + int(s * 0.02), c[1] - int(s * 0.08)),
            (30, 30, 30),
            -1,
        )
    else:
        raise ValueError(f"no drawing of {subject!r}; subjects: {', '.join(PICTURES)}")


PICTURES = {"cat": "animal", "fish": "animal", "car": "machine", "gear": "machine"}


def picture(subject: str, size: tuple[float, float] = (0.05, 0.05)) -> np.ndarray:
    """A picture card of an animal ("cat", "fish") or a machine ("car", "gear") with its name."""
    image = _canvas(size, f"picture-{subject}", (245, 240, 225), density=0.6)
    _drawing(image, subject)
    h, w = image.shape[:2]
    _text(image, subject.upper(), (w / 2.0, h * 0.85), 0.16 * h)
    return image


def domino_piece(index: int, size: tuple[float, float] = (0.08, 0.04)) -> np.ndarray:
    """Picture-domino piece ``index`` (1, 2, ...): its left half shows the right half of picture
    index - 1 and its right half the left half of picture ``index``, so pieces laid end to
    end complete the pictures (paper, "Domino": two pieces fit together to form an object)."""
    pictures = [_domino_picture(k, size) for k in (index - 1, index)]
    half = pictures[0].shape[1] // 2
    piece = np.hstack([pictures[0][:, half : 2 * half], pictures[1][:, :half]])
    cv2.line(piece, (half, 0), (half, piece.shape[0] - 1), (30, 30, 30), 5, cv2.LINE_AA)
    cv2.rectangle(piece, (0, 0), (piece.shape[1] - 1, piece.shape[0] - 1), (30, 30, 30), 6)
    return piece


def _domino_picture(k: int, size: tuple[float, float]) -> np.ndarray:
    """Picture ``k`` that two domino halves share, as big as a piece."""
    tint = 160 + _PALETTE[k % len(_PALETTE)] // 3
    image = _canvas(size, f"domino-picture-{k}", (int(tint[0]), int(tint[1]), int(tint[2])), density=0.9, border=None)
    h, w = image.shape[:2]
    cv2.circle(image, (w // 2, h // 2), int(0.42 * h), tuple(int(c) for c in _PALETTE[(k + 5) % 8]), 5, cv2.LINE_AA)
    _text(image, str(k), (w / 2.0, h / 2.0), 0.55 * h, colour=tuple(int(c) for c in _PALETTE[(k + 3) % 8]))
    return image


def hanoi_disk(index: int, size: tuple[float, float]) -> np.ndarray:
    """Tower-of-Hanoi disk ``index`` (1 smallest): a coloured plate with stripes and its number."""
    colours = {1: (220, 60, 60), 2: (60, 170, 70), 3: (60, 90, 210)}
    image = _canvas(size, f"hanoi-disk-{index}", colours.get(index, (200, 200, 200)), density=0.7)
    h, w = image.shape[:2]
    for x in range(w // 8, w, w // 4):
        cv2.line(image, (x, 0), (x + h // 2, h), (250, 250, 250), 3, cv2.LINE_AA)
    _text(image, str(index), (w / 2.0, h / 2.0), 0.6 * h)
    return image


def hanoi_base(size: tuple[float, float] = (0.12, 0.12)) -> np.ndarray:
    """A Tower-of-Hanoi base: the three are identical (they are told apart only by what is on
    them and around them, as the paper's rods), and sparsely drawn, so that what lies on a
    base dominates how its surroundings look."""
    image = _canvas(size, "hanoi-base", (200, 185, 160), density=0.25, border=(60, 40, 20))
    h, w = image.shape[:2]
    cv2.rectangle(image, (w // 6, h // 6), (w - w // 6, h - h // 6), (90, 60, 30), 4)
    return image


def baseline(size: tuple[float, float], arm: str) -> np.ndarray:
    """One arm ("long" along x or "short" along y) of the right-angle baseline: a ruler with
    centimetre ticks and numbers (so that each stretch of it looks different to SIFT)."""
    along_x = size[0] >= size[1]
    length, width = (size[0], size[1]) if along_x else (size[1], size[0])
    image = _canvas((length, width), f"baseline-{arm}", (245, 245, 240), density=0.4, border=(10, 10, 10))
    h, w = image.shape[:2]
    cm = PX_PER_M / 100.0
    for k in range(int(length * 100) + 1):
        x = int(round(k * cm))
        tick = h // 2 if k % 5 == 0 else h // 4
        cv2.line(image, (x, 0), (x, tick), (10, 10, 10), 3)
        if k % 2 == 0 and 0 < k < int(length * 100):
            _text(image, str(k), (x, h * 0.72), 0.35 * h, colour=(160, 20, 20) if arm == "long" else (20, 20, 160))
    return image if along_x else np.ascontiguousarray(np.rot90(image))


def label(word: str, size: tuple[float, float] = (0.1, 0.07)) -> np.ndarray:
    """A label card ('pond' or 'tree' in the puzzle task): a drawing and the word."""
    background = {"pond": (170, 210, 240), "tree": (200, 235, 180)}.get(word, (240, 240, 240))
    image = _canvas(size, f"label-{word}", background, density=0.5)
    h, w = image.shape[:2]
    if word == "pond":
        cv2.ellipse(
            image, (w // 2, int(h * 0.4)), (int(w * 0.3), int(h * 0.18)), 0, 0, 360, (40, 90, 200), -1, cv2.LINE_AA
        )
        for k in range(3):
            cv2.ellipse(image, (int(w * (0.35 + 0.15 * k)), int(h * 0.4)), (18, 6), 0, 0, 180, (220, 240, 255), 3)
    elif word == "tree":
        cv2.rectangle(image, (int(w * 0.46), int(h * 0.35)), (int(w * 0.54), int(h * 0.65)), (110, 70, 30), -1)
        cv2.circle(image, (w // 2, int(h * 0.3)), int(h * 0.2), (30, 130, 40), -1, cv2.LINE_AA)
    _text(image, word.upper(), (w / 2.0, h * 0.82), 0.2 * h)
    return image


def bin_plate(word: str, size: tuple[float, float] = (0.16, 0.12)) -> np.ndarray:
    """A labelled bin ("animals" or "machines"): a tray with a chequered rim and its word."""
    image = _canvas(size, f"bin-{word}", (230, 230, 230), density=0.3, border=(30, 30, 30))
    h, w = image.shape[:2]
    rim = max(12, h // 10)
    colour = (40, 140, 60) if word == "animals" else (60, 60, 170)
    for k, x in enumerate(range(0, w, rim)):
        cv2.rectangle(image, (x, 0), (x + rim, rim), colour if k % 2 else (250, 250, 250), -1)
        cv2.rectangle(image, (x, h - rim), (x + rim, h), (250, 250, 250) if k % 2 else colour, -1)
    _text(image, word.upper(), (w / 2.0, h - 2.2 * rim), 0.13 * h, colour=colour)
    return image
