"""Generalisation of vslsp.dmp: closed and nearly closed shapes, goals near and behind the start.

The amplitude factor s = (‖g − y0‖ A + E²) / (A² + E²) never divides by a vanishing quantity:
a drawn loop (A = 0) keeps its size for any goal, and nearly closed loops behave like it.
"""

import numpy as np
import pytest
from helpers.dmp import loop, rmse

from vslsp.dmp import DMP


def extent(y):
    """The largest distance (mm) of a path (T, D) from its first point."""
    return float(np.linalg.norm(y - y[0], axis=1).max())


@pytest.fixture(scope="module")
def closed():
    return DMP(2, n_basis=100).fit([loop(gap=0.0)])


def test_a_closed_loop_is_learned_and_g_equal_to_y0_reproduces_it(closed):
    t, y = loop(gap=0.0)
    assert closed.amplitude < 1e-12 and closed.extent == pytest.approx(40.0, rel=1e-3)
    rollout = closed.rollout(y[0], y[0], tau=t[-1], dt=t[1] - t[0], duration=t[-1])
    assert rmse(rollout.y, y) < 0.05  # mm, on a 40 mm loop
    assert closed.fit_rmse == pytest.approx(rmse(rollout.y, y), rel=1e-6)
    assert extent(rollout.y) == pytest.approx(extent(y), rel=0.01)


def test_a_closed_loop_drawn_to_a_new_goal_stays_a_loop_of_the_demonstrated_size(closed):
    t, y = loop(gap=0.0)
    for offset in ([10.0, 0.0], [0.0, -25.0], [60.0, 40.0]):
        goal = y[0] + offset
        rollout = closed.rollout(y[0], goal, tau=t[-1], dt=t[1] - t[0], duration=2 * t[-1])
        # The loop's shape, carried along to the goal: it spans its own 40 mm, plus the way there.
        span = np.ptp(rollout.y, axis=0)
        assert span.max() <= 40.0 + np.linalg.norm(offset) + 1.0
        assert span.max() >= 40.0 - 1.0
        assert np.linalg.norm(rollout.y[-1] - goal) < 0.01


@pytest.mark.parametrize("gap", [1e-3, 0.1, 1.0])
def test_nearly_closed_loops_do_not_blow_up(gap):
    t, y = loop(gap=gap)
    dmp = DMP(2, n_basis=100).fit([(t, y)])
    goal = y[0] + [10.0, 0.0]  # a goal 10 mm away, 10 000 times the gap at worst
    rollout = dmp.rollout(y[0], goal, tau=t[-1], dt=t[1] - t[0], duration=2 * t[-1])
    size = extent(y) + np.linalg.norm(goal - y[0])
    assert extent(rollout.y) <= 1.5 * size  # was 4.1e5 mm for a 1e-3 mm gap with s = ‖g − y0‖ / A
    assert np.linalg.norm(rollout.y[-1] - goal) < 0.01
    # Continuous in the gap: the nearly closed loop behaves like the closed one.
    closed = DMP(2, n_basis=100).fit([loop(gap=0.0)])
    reference = closed.rollout(y[0], goal, tau=t[-1], dt=t[1] - t[0], duration=2 * t[-1])
    assert rmse(rollout.y, reference.y) < 2.0 * gap + 0.05


def test_g_equal_to_y0_for_an_open_movement_draws_its_shape_and_comes_back(dmp, demo):
    """A reach rolled out to its own start: no transport, the lift's shape at a reduced size."""
    _, y = demo
    rollout = dmp.rollout(y[0], y[0], duration=2.0)
    assert np.all(np.isfinite(rollout.y))
    assert 0.0 < extent(rollout.y) <= dmp.extent + 1e-9  # s = E² / (A² + E²) <= 1
    assert np.linalg.norm(rollout.y[-1] - y[0]) < 1e-5


def test_excursions_are_bounded_by_the_demonstration_and_the_distance(dmp, demo):
    """Every rollout stays within a small multiple of the demonstration's size plus ‖g − y0‖."""
    _, y = demo
    rng = np.random.default_rng(7)
    starts = y[0] + rng.normal(0, 0.05, (300, 3))
    goals = starts + rng.normal(0, 1.0, (300, 1)) * rng.normal(0, 0.3, (300, 3))  # from 0 to ~1 m away
    rollout = dmp.rollout(starts, goals, duration=2.0)
    reach = np.linalg.norm(rollout.y - starts[:, None], axis=2).max(axis=1)
    distance = np.linalg.norm(goals - starts, axis=1)
    assert np.all(reach <= 2.0 * (extent(y) + distance))


def test_the_amplitude_factor_blends_distance_scaling_and_none(dmp, demo):
    _, y = demo
    a, e = dmp.amplitude, dmp.extent
    direction = (y[-1] - y[0]) / a
    assert dmp.scale(y[0], y[-1]) == pytest.approx(1.0)  # the demonstration itself
    assert dmp.scale(y[0], y[0]) == pytest.approx(e**2 / (a**2 + e**2))  # no distance: the shape alone
    far = dmp.scale(y[0], y[0] + 10 * a * direction)
    assert far == pytest.approx((10 * a * a + e**2) / (a**2 + e**2))
    straight = DMP(1).fit([(np.linspace(0, 1, 50), np.linspace(0, 2, 50)[:, None] ** 1)])
    assert straight.extent == pytest.approx(0.0, abs=1e-12)
    assert straight.scale(np.zeros(1), np.array([5.0])) == pytest.approx(2.5)  # pure transport: D / A


def test_a_goal_on_the_other_side_keeps_the_lift_and_does_not_blow_up(dmp, demo):
    """The paper's factor (g − y0) would flip the lift's sign per dimension (and has none for z,
    whose start and goal are level); one scalar keeps the forcing term's direction."""
    _, y = demo
    behind = y[0] - (y[-1] - y[0])
    rollout = dmp.rollout(y[0], behind, duration=2.0).y
    assert np.linalg.norm(rollout[-1] - behind) < 1e-5
    assert rollout[:, 2].max() == pytest.approx(y[:, 2].max(), rel=0.05)  # still lifts up ...
    assert rollout[:, 2].min() > y[0, 2] - 1e-3  # ... and never dips below the start height
    amplitude = np.linalg.norm(behind - y[0])
    assert np.linalg.norm(rollout - y[0], axis=1).max() < 2.5 * amplitude
