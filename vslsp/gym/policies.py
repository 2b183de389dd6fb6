"""VSL's reproduction (paper, Algorithm 1 part II) as a policy of ``vslsp/PandaTable-v0``: what
the tabletop experiments' robot does (:func:`~vslsp.experiments.tabletop_protocol.robot_operation`),
one pick-and-place per call.

For each recorded operation in the demonstrated order the policy looks at the observation seen
from above (:class:`~vslsp.vsl.pick_place.TableView`), finds the object and its place by match
finding and turns them into the hand's poses (:func:`~vslsp.vsl.reproduction.plan_operation`);
after an operation that picked and placed, it takes a last look and puts the object right once
when the execution left it off its place (:func:`~vslsp.vsl.reproduction.correction`).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from vslsp.geometry.poses import wrap
from vslsp.outcomes import NoMatch
from vslsp.vsl.pick_place import PickPlaceDemonstration, TableCamera, TableView
from vslsp.vsl.reproduction import PlannedOperation, correction, plan_operation


class VslPolicy:
    """The demonstrated operations of ``demonstration`` reproduced in the world a camera of
    calibration ``camera`` observes; call it with each observation (and the last step's info)."""

    def __init__(self, demonstration: PickPlaceDemonstration, camera: TableCamera) -> None:
        self.demonstration = demonstration
        self.view = TableView(camera)
        self.next = 0  # the operation to plan next
        self._done: PlannedOperation | None = None  # the last operation, until its last look

    @property
    def finished(self) -> bool:
        """Whether every operation was planned (and the last one looked at)."""
        return self.next >= len(self.demonstration.operations) and self._done is None

    def __call__(self, observation: np.ndarray, info: Mapping[str, Any] | None = None) -> np.ndarray | None:
        """The next action, (pick x, y, θ, place x, y, θ), for ``observation`` (H, W, 3), the
        camera's image; ``info``: the step's before it (its ``ok``: the execution picked and
        placed). None when nothing is left to do or the operation's object or place is not found."""
        seen = self.view.rectify(observation)
        if self._done is not None:
            done, self._done = self._done, None
            if info is None or info.get("ok", True):
                fix = correction(self.demonstration, self.next - 1, seen, self.view, done)
                if fix is not None:
                    return _action(fix)
        if self.next >= len(self.demonstration.operations):
            return None
        planned = plan_operation(self.demonstration, self.next, seen, self.view)
        self.next += 1
        if isinstance(planned, NoMatch):
            return None
        self._done = planned
        return _action(planned)


def _action(planned: PlannedOperation) -> np.ndarray:
    """The hand's poses as an action; the closing axes wrapped into [-π, π] (the fingers close
    alike, and the item turns by their difference modulo a full turn)."""
    pick, place = planned.pick, planned.place
    return np.array([pick[0], pick[1], wrap(pick[2]), place[0], place[1], wrap(place[2])], dtype=float)
