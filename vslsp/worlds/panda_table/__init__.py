"""The Panda table of VSL's real-world tasks (paper, "Real-world Experiments", Table 1): a Franka
Panda at a table of textured boxes, seen by an oblique camera.

Its seeded layouts are lists of (:class:`~vslsp.sim.tabletop.Item`,
:class:`~vslsp.sim.tabletop.Placement`) built from the objects, landmarks and scatterings of
:mod:`~vslsp.worlds.panda_table.layouts` (their pictures: :mod:`~vslsp.worlds.panda_table.textures`);
its observation is the camera's (H, W, 3) RGB image; the tutor puts an item at a ``Placement``;
the robot is the Panda (``pick_and_place``).
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from vslsp.sim.panda import Panda
from vslsp.sim.tabletop import Item, Placement, TabletopWorld
from vslsp.worlds.slips import Slip

if TYPE_CHECKING:
    from vslsp.perturbations import Drawn
    from vslsp.worlds.panda_table.perturbed import PerturbedView

SLIP_AREA = ((0.25, 0.80), (-0.38, 0.38))  # (x, y) m: where a nudged object's centre stays (in view, on the table)
_LEVEL = 0.003  # m: an item rests on what its bottom is this close to

__all__ = ["Item", "PandaTable", "Placement"]


class PandaTable(TabletopWorld):
    """The Panda table as a :class:`~vslsp.worlds.World`."""

    def __init__(self, layout: list[tuple[Item, Placement]], seed: int = 0, gui: bool = False) -> None:
        super().__init__(layout, seed, gui)
        # How far (x, y m) the tutor's slips carried each item from where the tutor put it, with
        # what it stands on (see :meth:`as_it_lies`).
        self.slipped: dict[str, tuple[float, float]] = {}
        self.perturbed: PerturbedView | None = None  # a reproduction's perturbation (:meth:`perturb`)

    @classmethod
    def from_layout(cls, layout: list[tuple[Item, Placement]], seed: int = 0, gui: bool = False) -> PandaTable:
        return cls(layout, seed, gui)

    def perturb(self, drawn: Drawn) -> PerturbedView:
        """Apply the perturbation ``drawn`` to this (reproduction) world: its camera moved, its
        distractors put on the table, and every observation from now on seen as it makes it
        (:class:`~vslsp.worlds.panda_table.perturbed.PerturbedView`)."""
        from vslsp.worlds.panda_table.perturbed import PerturbedView

        self.perturbed = PerturbedView(self, drawn)
        return self.perturbed

    def observe(self) -> np.ndarray:
        """The camera's RGB image (960, 1280, 3) uint8 (arm parked), as a perturbation sees it."""
        image = super().observe()
        return image if self.perturbed is None else self.perturbed.see(image)

    def tutor_move(self, name: str, where: Placement) -> None:
        """The tutor puts item ``name`` at ``where`` by hand: it lies as the tutor put it, on
        what it stands on (which keeps its own slip)."""
        self.slipped[name] = self.slipped.get(where.on, (0.0, 0.0)) if where.on else (0.0, 0.0)
        self.tutor_place(name, where)

    def as_it_lies(self, where: Placement) -> Placement:
        """``where``, meant on an item where the tutor put it, on that item as it lies: moved
        with it when the tutor's slip nudged it (or what it stands on). A tutor stacks a disk on
        the one below it, wherever the hand's slip left that one; stacked over the base's
        centre instead, the disk would hang off it (the Tower of Hanoi). Without slips,
        ``where`` itself."""
        dx, dy = self.slipped.get(where.on, (0.0, 0.0)) if where.on else (0.0, 0.0)
        return replace(where, x=where.x + dx, y=where.y + dy) if (dx, dy) != (0.0, 0.0) else where

    @property
    def robot(self) -> Panda:
        return self.panda

    def truth(self, name: str) -> tuple[float, float, float, float]:
        """Item ``name``'s pose: x, y, z (its bottom, m), yaw (rad)."""
        return self.pose(name)

    # -- the tutor's slips (vslsp.worlds.slips) --------------------------------------------
    def slip_candidates(self, operated: str) -> list[str]:
        """What the tutor's hand may disturb while operating ``operated``: every other movable
        item in view that carries nothing and lies on the table or on a static landmark (a
        base, a bin, a label), in the world's order: the items the task goes on to operate on
        and those it has put in place already."""
        return [
            name
            for name, item in self.specs.items()
            if item.movable
            and name != operated
            and _inside(self.pose(name), SLIP_AREA)
            and not self._carried_by(name)
            and self._support(name) != ""
        ]

    def nudge(self, slip: Slip) -> Slip | None:
        """Apply the tutor's ``slip`` (m, deg) to its object, which stays on what it lies on:
        moved by it, or the other way when that way would leave :data:`SLIP_AREA` or its
        support, or come closer to another item than their footprints' discs allow (unless it
        was that close already); the world settles. Returns the slip applied, or None when
        neither way is free."""
        x, y, _, yaw = self.pose(slip.name)
        support = self._support(slip.name) or None
        for way in slip.both_ways():
            moved = (x + way.dx_m, y + way.dy_m)
            if self._free(slip.name, support, (x, y), moved):
                before = self.slipped.get(slip.name, (0.0, 0.0))
                self.slipped[slip.name] = (before[0] + way.dx_m, before[1] + way.dy_m)
                self.tutor_place(slip.name, Placement(*moved, yaw + float(np.radians(way.dyaw_deg)), on=support))
                return way
        return None

    def _radius(self, name: str) -> float:
        return float(np.hypot(*self.specs[name].size[:2])) / 2.0

    def _carried_by(self, name: str) -> bool:
        """Whether another item lies on ``name``."""
        x, y, z, _ = self.pose(name)
        top = z + self.specs[name].size[2]
        return any(
            abs(self.pose(other)[2] - top) < _LEVEL
            and np.hypot(self.pose(other)[0] - x, self.pose(other)[1] - y) < self._radius(name)
            for other in self.specs
            if other != name
        )

    def _support(self, name: str) -> str | None:
        """What ``name`` lies on: None (the table), a static item's name, or "" (another movable item)."""
        x, y, z, _ = self.pose(name)
        if z < _LEVEL:
            return None
        for other, item in self.specs.items():
            ox, oy, oz, _ = self.pose(other)
            if other != name and abs(oz + item.size[2] - z) < _LEVEL and np.hypot(ox - x, oy - y) < self._radius(other):
                return other if not item.movable else ""
        return ""

    def _free(self, name: str, support: str | None, old: tuple[float, float], new: tuple[float, float]) -> bool:
        if not _inside(new, SLIP_AREA):
            return False
        if support is not None:  # stays on its support: its centre over the support's top
            sx, sy, _, syaw = self.pose(support)
            along = (new[0] - sx) * np.cos(syaw) + (new[1] - sy) * np.sin(syaw)
            across = -(new[0] - sx) * np.sin(syaw) + (new[1] - sy) * np.cos(syaw)
            half = np.array(self.specs[support].size[:2]) / 2.0 - 0.01
            if abs(along) > half[0] or abs(across) > half[1]:
                return False
        for other in self.specs:
            if other in (name, support):
                continue
            ox, oy = self.pose(other)[:2]
            reach = self._radius(name) + self._radius(other)
            if np.hypot(new[0] - ox, new[1] - oy) < min(np.hypot(old[0] - ox, old[1] - oy), reach):
                return False
        return True


def _inside(pose, area: tuple[tuple[float, float], tuple[float, float]]) -> bool:
    return area[0][0] <= pose[0] <= area[0][1] and area[1][0] <= pose[1] <= area[1][1]
