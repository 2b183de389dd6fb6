"""The part every simulated world shares: its own pybullet client, closed once, usable in ``with``."""

from __future__ import annotations

from typing import Self

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
