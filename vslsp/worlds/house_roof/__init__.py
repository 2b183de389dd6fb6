"""The house-roof board of VSL's simulation (paper, "Simulation", Figure 4): three identical house
bodies and three identical roofs on a board with a baseline, in 2-D, without a simulator.

Its seeded layout is a :class:`~vslsp.worlds.house_roof.board.HouseWorld` (the ground truth as a
value, :meth:`~vslsp.worlds.house_roof.board.HouseWorld.random`), drawn with the sprites of
:mod:`~vslsp.worlds.house_roof.sprites`; its observation the rendered (H, W, 3) RGB image; the
tutor lifts a roof (``where`` None) or puts it at a pose (x, y px, θ rad); there is no robot (the
reproduction plans the hand's path and lets the grasped roof land where it ends).
"""

from __future__ import annotations

import numpy as np

from vslsp.geometry.poses import Pose2
from vslsp.worlds.house_roof.board import HouseWorld

__all__ = ["HouseBoard", "HouseWorld", "roof_name"]


def roof_name(index: int) -> str:
    """The name of roof ``index`` (0, 1, 2)."""
    return f"roof-{index}"


class HouseBoard:
    """The house-roof board as a :class:`~vslsp.worlds.World`: ``state`` is the ground truth now."""

    robot = None

    def __init__(self, state: HouseWorld) -> None:
        self.state = state

    @classmethod
    def from_layout(cls, layout: HouseWorld, seed: int = 0) -> HouseBoard:
        return cls(layout)

    def observe(self) -> np.ndarray:
        """The board as the camera sees it: (H, W, 3) uint8 RGB."""
        return self.state.render()

    def tutor_move(self, name: str, where: Pose2 | None) -> None:
        """The tutor lifts roof ``name`` (``where`` None: in the hand, out of view) or puts it at ``where``."""
        self.state = self.state.with_roof(_index(name), where)

    def truth(self, name: str) -> Pose2 | None:
        """Roof ``name``'s pose (None while in the hand)."""
        return self.state.roofs[_index(name)]

    def close(self) -> None:
        """Nothing to release: the board is an image."""


def _index(name: str) -> int:
    return int(name.removeprefix("roof-"))
