"""The Panda's wrist branch (vslsp.sim.pick_place.wrist_branch): the fingers' closing axes at the
pick and the place, shifted by a multiple of pi together, keep joint 7 inside its limits, the
shorter way round when it can and the longer way when only that fits; the item always turns by
the same angle (mod 2 pi)."""

from __future__ import annotations

import numpy as np
import pytest

from vslsp.sim.panda import UPPER, Panda
from vslsp.sim.pick_place import wrist_branch


def inside(x: float, y: float, theta: float) -> bool:
    return abs(Panda.wrist_angle(x, y, theta)) < UPPER[6]


def turned(pick_theta: float, place_theta: float) -> float:
    return float(np.angle(np.exp(1j * (place_theta - pick_theta))))


def test_a_half_turn_the_shorter_way_cannot_make_goes_the_longer_way():
    # stacking seed 40, two views: the teddy picked at y = 0.03 and put at y = -0.13 turned by
    # 178.6 deg; the shorter way needs joint 7 at -3.02 rad, past its limit.
    pick, place = np.array([0.473, 0.0265, np.radians(-68.4)]), np.array([0.4053, -0.132, np.radians(110.2)])
    theta_pick, theta_place = wrist_branch(pick, place)
    assert inside(*pick[:2], theta_pick) and inside(*place[:2], theta_place)
    assert turned(theta_pick, theta_place) == pytest.approx(turned(pick[2], place[2]))
    assert abs(theta_place - theta_pick) > np.pi  # the longer way round


@pytest.mark.parametrize("turn_deg", [0.0, 30.0, -90.0, 150.0])
def test_a_turn_the_shorter_way_can_make_is_made_that_way(turn_deg):
    pick = np.array([0.5, 0.1, np.radians(20.0)])
    place = np.array([0.55, -0.1, np.radians(20.0 + turn_deg)])
    theta_pick, theta_place = wrist_branch(pick, place)
    assert theta_place - theta_pick == pytest.approx(np.radians(turn_deg))
    assert inside(*pick[:2], theta_pick) and inside(*place[:2], theta_place)
