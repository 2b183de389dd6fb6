"""The Panda table of VSL's real-world tasks (paper, "Real-world Experiments", Table 1): a Franka
Panda at a table of textured boxes, seen by an oblique camera.

Its seeded layouts are lists of (:class:`~vslsp.sim.tabletop.Item`,
:class:`~vslsp.sim.tabletop.Placement`) built from the objects, landmarks and scatterings of
:mod:`~vslsp.worlds.panda_table.layouts` (their pictures: :mod:`~vslsp.worlds.panda_table.textures`);
its observation is the camera's (H, W, 3) RGB image; the tutor puts an item at a ``Placement``;
the robot is the Panda (``pick_and_place``).
"""

from __future__ import annotations

from vslsp.sim.panda import Panda
from vslsp.sim.tabletop import Item, Placement, TabletopWorld

__all__ = ["Item", "PandaTable", "Placement"]


class PandaTable(TabletopWorld):
    """The Panda table as a :class:`~vslsp.worlds.World`."""

    @classmethod
    def from_layout(cls, layout: list[tuple[Item, Placement]], seed: int = 0, gui: bool = False) -> PandaTable:
        return cls(layout, seed, gui)

    def tutor_move(self, name: str, where: Placement) -> None:
        """The tutor puts item ``name`` at ``where`` by hand."""
        self.tutor_place(name, where)

    @property
    def robot(self) -> Panda:
        return self.panda

    def truth(self, name: str) -> tuple[float, float, float, float]:
        """Item ``name``'s pose: x, y, z (its bottom, m), yaw (rad)."""
        return self.pose(name)
