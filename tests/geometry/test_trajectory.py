"""The pick-and-place trajectory of the original VSL: cubic paths, the tanh⁻¹ height profile,
cubic time scaling and the trapezoidal rotation profile, over a rest → pick → place → rest cycle."""

import numpy as np
import pytest

from vslsp.errors import InputError
from vslsp.geometry.trajectory import (
    PAPER_H0,
    TrajectoryParameters,
    cubic_path,
    height_profile,
    pick_and_place,
    time_scaling,
    trapezoidal_profile,
)

REST, PICK, PLACE = np.array([0.0, 0.0, 0.2]), np.array([0.3, -0.1, 0.0]), np.array([0.1, 0.25, 0.04])


def cycle(**kwargs):
    parameters = TrajectoryParameters(**kwargs) if kwargs else TrajectoryParameters(samples=201)
    return pick_and_place(REST, PICK, PLACE, theta_pick=0.6, theta_place=-1.1, parameters=parameters)


def test_the_cycle_passes_rest_pick_place_and_returns_to_rest():
    trajectory = cycle()
    assert trajectory.key_points == pytest.approx(np.array([REST, PICK, PLACE]))
    assert trajectory.xyz[-1] == pytest.approx(REST)
    assert trajectory.t[0] == 0.0 and trajectory.t[-1] == pytest.approx(7.0)
    assert np.all(np.diff(trajectory.t) > 0)  # key points shared, not repeated
    assert trajectory.xyz.shape == (len(trajectory.t), 3) and trajectory.theta.shape == trajectory.t.shape


def test_the_hand_is_at_rest_at_every_key_point():
    trajectory = cycle()
    velocity = np.gradient(trajectory.xyz, trajectory.t, axis=0)
    speed_scale = np.abs(velocity).max()
    for index in (0, trajectory.segments[1], trajectory.segments[2], len(trajectory.t) - 1):
        assert np.abs(velocity[index]).max() < 0.03 * speed_scale
    assert np.abs(velocity[len(trajectory.t) // 6]).max() > 0.3 * speed_scale  # it does move in between


def test_the_xy_path_is_the_cubic_of_the_end_conditions():
    s = np.linspace(0.0, 1.0, 11)
    path = cubic_path([1.0, 2.0], [3.0, -2.0], s, start_velocity=[0.5, 0.0], end_velocity=[0.0, 1.0])
    assert path[0] == pytest.approx([1.0, 2.0]) and path[-1] == pytest.approx([3.0, -2.0])
    slope = np.gradient(
        cubic_path([1.0, 2.0], [3.0, -2.0], np.linspace(0, 1, 10001), [0.5, 0.0], [0.0, 1.0]), 1e-4, axis=0
    )
    assert slope[0] == pytest.approx([0.5, 0.0], abs=5e-3) and slope[-1] == pytest.approx([0.0, 1.0], abs=5e-3)
    # With zero end velocities it is the smooth step 3s^2 - 2s^3 along the straight line.
    straight = cubic_path([0.0, 0.0], [2.0, 4.0], s)
    assert straight[:, 1] == pytest.approx(2.0 * straight[:, 0])
    assert straight[:, 0] == pytest.approx(2.0 * (3 * s**2 - 2 * s**3))


@pytest.mark.parametrize("h0, kappa", [(PAPER_H0, 2.0), (1.0, 1.0), (1.9, 3.5), (0.2, 0.5)])
def test_the_height_profile_is_zero_at_the_ends_and_highest_mid_way(h0, kappa):
    s = np.linspace(0.0, 1.0, 1001)
    z = height_profile(s, 0.1, h0, kappa)
    assert z[0] == pytest.approx(0.0, abs=1e-12) and z[-1] == pytest.approx(0.0, abs=1e-12)
    assert np.argmax(z) == 500 and z[500] == pytest.approx(0.1)
    assert np.all(np.diff(z[:501]) >= 0) and np.all(np.diff(z[500:]) <= 0)
    assert z == pytest.approx(z[::-1])  # symmetric


def test_with_the_paper_s_h0_the_profile_is_the_printed_formula():
    s = np.linspace(0.0, 1.0, 101)
    printed = 0.1 * (1.0 - np.abs(np.arctanh(PAPER_H0 * (s - 0.5)) ** 2))
    assert height_profile(s, 0.1, PAPER_H0, 2.0) == pytest.approx(printed)


def test_the_hand_lifts_by_h_between_pick_and_place_at_different_levels():
    trajectory = cycle()
    i, j = trajectory.segments[1], trajectory.segments[2]
    middle = (i + j) // 2
    assert trajectory.xyz[middle, 2] == pytest.approx(0.5 * (PICK[2] + PLACE[2]) + 0.05)
    assert trajectory.xyz[i : j + 1, 2].min() >= min(PICK[2], PLACE[2]) - 1e-12


def test_time_scaling_is_the_cubic_between_t_start_and_t_final():
    t = np.linspace(1.0, 3.0, 2001)
    s = time_scaling(t, 1.0, 3.0)
    assert s[0] == 0.0 and s[-1] == 1.0 and s[1000] == pytest.approx(0.5)
    rate = np.gradient(s, t)
    assert abs(rate[0]) < 2e-3 and abs(rate[-1]) < 2e-3 and rate[1000] == pytest.approx(0.75, rel=1e-3)
    assert np.all(np.diff(s) >= 0)
    assert time_scaling(np.array([0.0, 4.0]), 1.0, 3.0) == pytest.approx([0.0, 1.0])


def test_the_rotation_profile_is_trapezoidal_and_monotone():
    tau = np.linspace(0.0, 1.0, 4001)
    theta = trapezoidal_profile(tau, 0.4, -1.2, blend=0.25)
    assert theta[0] == pytest.approx(0.4) and theta[-1] == pytest.approx(-1.2)
    assert np.all(np.diff(theta) <= 1e-12)  # monotone towards the end value
    speed = -np.gradient(theta, tau)
    flat = speed[(tau > 0.27) & (tau < 0.73)]
    assert flat == pytest.approx(np.full_like(flat, 1.6 / 0.75), rel=1e-3)  # constant cruise
    rising = speed[(tau > 0.01) & (tau < 0.24)]
    assert np.all(np.diff(rising) > 0) and np.diff(rising) == pytest.approx(
        np.full(len(rising) - 1, np.diff(rising).mean()), rel=1e-2
    )
    assert speed[0] == pytest.approx(0.0, abs=0.01) and speed[-1] == pytest.approx(0.0, abs=0.01)


def test_the_hand_turns_to_theta_pick_then_theta_place_then_back():
    trajectory = cycle()
    i, j = trajectory.segments[1], trajectory.segments[2]
    assert trajectory.theta[0] == 0.0 and trajectory.theta[-1] == pytest.approx(0.0)
    assert trajectory.theta[i] == pytest.approx(0.6) and trajectory.theta[j] == pytest.approx(-1.1)
    assert np.all(np.diff(trajectory.theta[: i + 1]) >= 0)
    assert np.all(np.diff(trajectory.theta[i : j + 1]) <= 0)
    assert np.all(np.diff(trajectory.theta[j:]) >= 0)


def test_to_dict_carries_the_arrays_and_the_parameters():
    data = cycle(samples=5).to_dict()
    assert len(data["t"]) == len(data["xyz"]) == len(data["theta"]) == 13
    assert data["segments"] == [0, 4, 8] and data["parameters"]["samples"] == 5


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"h0": 2.0}, "h0 must lie in"),
        ({"h0": -0.5}, "h0 must lie in"),
        ({"kappa": 0.0}, "kappa"),
        ({"height": -0.01}, "height"),
        ({"durations": (1.0, 0.0, 1.0)}, "durations"),
        ({"samples": 1}, "samples"),
        ({"blend": 0.7}, "blend"),
    ],
)
def test_bad_parameters_are_input_errors(kwargs, message):
    with pytest.raises(InputError, match=message):
        TrajectoryParameters(**kwargs)


def test_t_final_not_after_t_start_is_an_input_error():
    with pytest.raises(InputError, match="t_final must be later than t_start"):
        time_scaling(np.array([0.0]), 2.0, 2.0)


def test_key_points_must_be_three_dimensional():
    with pytest.raises(InputError, match="three finite numbers"):
        pick_and_place(REST, PICK[:2], PLACE, 0.0, 0.0)
