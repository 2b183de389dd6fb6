"""Procedural textures of the iCub's cubes (paper, VSL-SP "Implementation": the cubes have "the
same size but different colors and textures").

VSL finds an object again by SIFT match finding (Lowe 2004), which needs keypoints on the
object; a plain cube gives almost none. Each face of a cube carries seeded confetti (discs,
triangles and strokes) in darker and brighter shades of the cube's own colour: the shades
differ in brightness, which SIFT sees, and share the colour's hue, which names the object's
symbol (colour naming is the saturation-weighted mean hue, so the symbol is unchanged). The
same name gives the same pixels; every face of a cube and every cube name draws its own
pattern, so that the faces of one cube and two cubes of one colour do not look alike.
"""

from __future__ import annotations

import hashlib
import os
import zlib
from pathlib import Path

import cv2
import numpy as np

from vslsp.files import cache_folder

FACE_PX = 48  # texture pixels along a face's side: about what the head camera sees (TinyRenderer samples
# textures without filtering, so a finer texture only aliases)
SHADES = (0.3, 0.5, 1.5)  # the confetti's shades of the cube's colour (see _shade). Contrast is what SIFT
# needs (shades 0.45/1.3 matched 84 % of VSL's steps, these 93 %); the pale ones (1.5 mixes in half white)
# leave small holes in the object mask, so its centroid moves by up to about 3 px, and on a shaded face the
# darkest green and purple spots read as landmark grey: far, colour names and change detection absorb both
# (tests/vsl/test_grounding_textured.py, tests/vsl/test_grounding_sim.py)
ATLAS = (2, 3)  # rows, columns of faces in a cube's texture atlas
CONFETTI = 8  # shapes per face: a few large blobs, which SIFT finds again from another view
SHAPE_SCALE = 2.5  # the shapes' size (radius 5-11 px of a 48 px face)


def _shade(colour: tuple[float, float, float], factor: float) -> tuple[int, int, int]:
    """A shade of ``colour`` (RGB in [0, 1]) as uint8 RGB: ``factor`` <= 1 scales its
    brightness (the hue stays); ``factor`` > 1 mixes it with ``factor - 1`` of white (the hue
    stays, the saturation drops)."""
    rgb = np.asarray(colour, dtype=float) * 255.0
    rgb = rgb * factor if factor <= 1.0 else rgb + (255.0 - rgb) * (factor - 1.0)
    r, g, b = (int(v) for v in np.clip(np.round(rgb), 0, 255))
    return r, g, b


def cube_face(colour: tuple[float, float, float], name: str, size: int | None = None) -> np.ndarray:
    """One face (size, size, 3) uint8 RGB: ``colour`` (RGB in [0, 1]) under seeded confetti in
    its shades; ``name`` seeds the pattern."""
    size = size or FACE_PX
    rng = np.random.default_rng(zlib.crc32(name.encode("utf-8")))
    face = np.empty((size, size, 3), np.uint8)
    face[:] = _shade(colour, 1.0)
    unit = size / 96.0 * SHAPE_SCALE
    for _ in range(CONFETTI):
        shade = _shade(colour, float(rng.choice(SHADES)))
        x, y = int(rng.integers(size)), int(rng.integers(size))
        r = max(2, int(round(rng.uniform(4.0, 9.0) * unit)))
        kind = int(rng.integers(3))
        if kind == 0:
            cv2.circle(face, (x, y), r, shade, -1, cv2.LINE_AA)
        elif kind == 1:
            angle = rng.uniform(0, 2 * np.pi)
            points = [(x + 1.6 * r * np.cos(angle + a), y + 1.6 * r * np.sin(angle + a)) for a in (0.0, 2.2, 4.0)]
            cv2.fillPoly(face, [np.round(points).astype(np.int32)], shade, cv2.LINE_AA)
        else:
            angle = rng.uniform(0, np.pi)
            dx, dy = 2.0 * r * np.cos(angle), 2.0 * r * np.sin(angle)
            cv2.line(
                face,
                (int(x - dx), int(y - dy)),
                (int(x + dx), int(y + dy)),
                shade,
                max(2, int(round(3 * unit))),
                cv2.LINE_AA,
            )
    return face


def cube_atlas(colour: tuple[float, float, float], name: str, size: int | None = None) -> np.ndarray:
    """The six faces of cube ``name`` in an atlas (2 size, 3 size, 3) uint8 RGB: face k at row
    k // 3, column k % 3 (see :func:`cube_mesh`)."""
    rows, columns = ATLAS
    faces = [cube_face(colour, f"{name}/face{k}", size) for k in range(rows * columns)]
    return np.vstack([np.hstack(faces[r * columns : (r + 1) * columns]) for r in range(rows)])


def cube_mesh(size: float) -> tuple[list, list, list, list]:
    """Vertices, triangle indices, texture coordinates and normals of a cube of side ``size``
    (m) centred on its origin, face k textured by tile k of :func:`cube_atlas`."""
    h = size / 2.0
    faces = [  # corners counter-clockwise seen from outside, and the face's normal
        ([(-h, h, h), (-h, -h, h), (h, -h, h), (h, h, h)], (0, 0, 1)),
        ([(-h, h, -h), (h, h, -h), (h, -h, -h), (-h, -h, -h)], (0, 0, -1)),
        ([(h, -h, -h), (h, h, -h), (h, h, h), (h, -h, h)], (1, 0, 0)),
        ([(-h, h, -h), (-h, -h, -h), (-h, -h, h), (-h, h, h)], (-1, 0, 0)),
        ([(h, h, -h), (-h, h, -h), (-h, h, h), (h, h, h)], (0, 1, 0)),
        ([(-h, -h, -h), (h, -h, -h), (h, -h, h), (-h, -h, h)], (0, -1, 0)),
    ]
    rows, columns = ATLAS
    vertices, indices, uvs, normals = [], [], [], []
    for k, (corners, normal) in enumerate(faces):
        u0, u1 = (k % columns) / columns, (k % columns + 1) / columns
        v_top, v_bottom = 1.0 - (k // columns) / rows, 1.0 - (k // columns + 1) / rows  # v runs up the atlas
        vertices += [list(c) for c in corners]
        normals += [list(normal)] * 4
        uvs += [[u0, v_top], [u0, v_bottom], [u1, v_bottom], [u1, v_top]]
        indices += [4 * k, 4 * k + 1, 4 * k + 2, 4 * k, 4 * k + 2, 4 * k + 3]
    return vertices, indices, uvs, normals


def texture_file(image: np.ndarray) -> Path:
    """A PNG of ``image`` (H, W, 3) uint8 RGB for pybullet's ``loadTexture``, written once into
    the cache folder, named by its content."""
    image = np.ascontiguousarray(image)
    digest = hashlib.sha256(image.tobytes() + str(image.shape).encode()).hexdigest()[:16]
    cache = cache_folder()
    path = cache / f"texture-{digest}.png"
    if not path.exists():
        partial = cache / f"texture-{digest}.{os.getpid()}.tmp.png"
        # Encoded here and written by Python: a full disk is then an OSError saying so (ENOSPC),
        # where cv2.imwrite would only return False.
        encoded = cv2.imencode(".png", cv2.cvtColor(image, cv2.COLOR_RGB2BGR))[1].tobytes()
        try:
            partial.write_bytes(encoded)
            os.replace(partial, path)
        finally:
            partial.unlink(missing_ok=True)
    return path
