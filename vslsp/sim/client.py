"""The part every simulated world shares: its own pybullet client, closed once, usable in ``with``."""

from __future__ import annotations

from typing import Self

import numpy as np

from vslsp.sim.quiet import quiet

with quiet():
    import pybullet as pb


def mesh_visual(client: int, mesh: tuple[list, list, list, list]) -> int:
    """A white visual shape from a textured ``mesh`` (vertices, indices, uvs, normals); the
    texture is applied to the body afterwards with ``changeVisualShape``."""
    vertices, indices, uvs, normals = mesh
    return pb.createVisualShape(
        pb.GEOM_MESH,
        vertices=vertices,
        indices=indices,
        uvs=uvs,
        normals=normals,
        rgbaColor=[1, 1, 1, 1],
        physicsClientId=client,
    )


def strip_mesh(half: tuple[float, float, float], segments: int) -> tuple[list, list, list, list]:
    """Vertices, triangle indices, texture coordinates and normals of a box of half extents
    ``half`` (m) cut into ``segments`` pieces along its y axis.

    TinyRenderer tests every pixel of a triangle's screen bounding box: a long, thin box seen
    at an angle (the landmark line, 0.8 m) has triangles whose boxes cover much of the view and
    cost about 25 ms a 640x480 render; cut in 16 pieces the same colours come out (byte for
    byte; the depth within 1e-6 m) for a few milliseconds."""
    hx, hy, hz = half
    ys = np.linspace(-hy, hy, segments + 1)
    vertices: list[list[float]] = []
    indices: list[int] = []
    normals: list[list[float]] = []

    def quad(corners: list[tuple[float, float, float]], normal: tuple[float, float, float]) -> None:
        k = len(vertices)
        vertices.extend([float(c) for c in corner] for corner in corners)
        normals.extend([[float(n) for n in normal]] * 4)
        indices.extend([k, k + 1, k + 2, k, k + 2, k + 3])

    for y0, y1 in zip(ys[:-1], ys[1:]):
        quad([(-hx, y1, hz), (-hx, y0, hz), (hx, y0, hz), (hx, y1, hz)], (0, 0, 1))
        quad([(-hx, y1, -hz), (hx, y1, -hz), (hx, y0, -hz), (-hx, y0, -hz)], (0, 0, -1))
        quad([(hx, y0, -hz), (hx, y1, -hz), (hx, y1, hz), (hx, y0, hz)], (1, 0, 0))
        quad([(-hx, y1, -hz), (-hx, y0, -hz), (-hx, y0, hz), (-hx, y1, hz)], (-1, 0, 0))
    quad([(hx, hy, -hz), (-hx, hy, -hz), (-hx, hy, hz), (hx, hy, hz)], (0, 1, 0))
    quad([(-hx, -hy, -hz), (hx, -hy, -hz), (hx, -hy, hz), (-hx, -hy, hz)], (0, -1, 0))
    return vertices, indices, [[0.0, 0.0]] * len(vertices), normals


class PhysicsClient:
    """A world that owns the pybullet client ``self.client`` (None once closed)."""

    client: int | None = None

    @property
    def live_client(self) -> int:
        """The pybullet client id; an error once the world is closed."""
        if self.client is None:
            raise RuntimeError(f"{type(self).__name__} is closed: build a new world")
        return self.client

    def close(self) -> None:
        if self.client is not None:
            pb.disconnect(self.client)
            self.client = None

    def __enter__(self) -> Self:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
