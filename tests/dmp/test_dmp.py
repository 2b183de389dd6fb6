"""The DMP of vslsp.dmp: learning, reproduction, convergence to the goal, τ, batches, couplings.

The demonstrations are smooth reaches: a minimum-jerk move from start to goal plus a lift that
rises and falls back (zero velocity at both ends), like a hand going over the table.
"""

import numpy as np
import pytest
import torch
from helpers.dmp import reach, rmse

from vslsp.dmp import DMP, Rollout


# -- learning and reproduction ---------------------------------------------------------------
def test_fit_reproduces_a_smooth_demonstration_within_a_tenth_of_a_millimetre(dmp, demo):
    t, y = demo
    rollout = dmp.rollout(y[0], y[-1], tau=t[-1], dt=t[1] - t[0], duration=t[-1])
    assert rollout.y.shape == y.shape
    assert rmse(rollout.y, y) < 1e-4
    assert dmp.fit_rmse == pytest.approx(rmse(rollout.y, y), rel=1e-6)
    assert (dmp.n_demos, dmp.tau, dmp.dt) == (1, pytest.approx(1.0), pytest.approx(0.01))
    assert dmp.amplitude == pytest.approx(np.linalg.norm(y[-1] - y[0]))
    assert 0.05 < dmp.extent < 0.15  # the lift, off the start-goal line


def test_rollout_returns_time_position_velocity_and_acceleration_that_agree(dmp, demo):
    t, y = demo
    rollout = dmp.rollout(y[0], y[-1])
    assert isinstance(rollout, Rollout)
    assert rollout.t == pytest.approx(np.arange(131) * 0.01)  # 1.3 τ by default
    assert rollout.y.shape == rollout.yd.shape == rollout.ydd.shape == (131, 3)
    assert rollout.y[0] == pytest.approx(y[0], abs=1e-12)
    assert np.abs(rollout.yd[0]).max() == 0.0  # starts at rest
    # The velocity is the derivative of the position, and the acceleration that of the velocity
    # (sampled finer than the forcing term's holds of τ / 1000, across which ÿ steps).
    fine = dmp.rollout(y[0], y[-1], dt=0.0001)
    assert np.gradient(fine.y, 0.0001, axis=0)[1:-1] == pytest.approx(fine.yd[1:-1], abs=1e-5)
    integral = np.concatenate([np.zeros((1, 3)), np.cumsum((fine.ydd[1:] + fine.ydd[:-1]) / 2 * 0.0001, axis=0)])
    assert integral == pytest.approx(fine.yd, abs=0.01 * np.abs(fine.yd).max())


def test_several_demonstrations_with_their_own_starts_goals_and_durations():
    """The same reach from three places, at three speeds and sample rates: one DMP fits all."""
    demos = [
        reach((0.0, 0.0, 0.0), (0.3, -0.2, 0.0), duration=1.0, samples=101),
        reach((0.1, 0.05, 0.02), (0.4, -0.15, 0.02), duration=0.7, samples=141),
        reach((-0.2, 0.1, -0.05), (0.1, -0.1, -0.05), duration=1.6, samples=81),
    ]
    dmp = DMP(3).fit(demos)
    assert dmp.n_demos == 3
    assert dmp.tau == pytest.approx(np.mean([1.0, 0.7, 1.6]))
    assert dmp.fit_rmse < 2e-4
    for t, y in demos:
        rollout = dmp.rollout(y[0], y[-1], tau=t[-1], dt=t[1] - t[0], duration=t[-1])
        assert rmse(rollout.y, y) < 1e-3


def test_a_tuple_of_demonstrations_is_accepted_like_a_list(demo):
    assert DMP(3).fit((demo,)).weights == pytest.approx(DMP(3).fit([demo]).weights, abs=0)


def test_fitting_is_deterministic(demo):
    assert np.array_equal(DMP(3).fit([demo]).weights, DMP(3).fit([demo]).weights)


# -- convergence to the goal -------------------------------------------------------------------
def test_the_forcing_term_is_zero_from_tau_on(dmp):
    x_tau = np.exp(-dmp.alpha_x)
    phases = x_tau * np.array([1.0, 0.999, 0.5, 1e-6])  # τ and later
    assert np.all(dmp.forcing(phases) == 0.0)
    assert np.abs(dmp.forcing(np.array([1.0, 0.5, 0.1]))).max() > 1.0  # ... and not before


def test_after_tau_every_movement_stays_within_a_tenth_of_a_millimetre_of_its_goal(dmp):
    rng = np.random.default_rng(1)
    starts, goals = rng.uniform(-0.3, 0.3, (200, 3)), rng.uniform(-0.3, 0.3, (200, 3))
    rollout = dmp.rollout(starts, goals, duration=2.0)  # τ = 1 s
    after = np.linalg.norm(rollout.y[:, 100:] - goals[:, None], axis=2)
    assert after.max() < 1e-4
    # The bound of the formulation: the free spring's remainder P(1) (y0 − g) and none of f.
    distance = np.linalg.norm(goals - starts, axis=1)
    p1 = (1 + dmp.omega) * np.exp(-dmp.omega)
    assert np.all(after.max(axis=1) <= p1 * distance * (1 + 1e-9) + 1e-12)
    assert np.abs(rollout.yd[:, 100:]).max() < 1e-3


def test_the_default_rollout_ends_within_a_hundredth_of_a_millimetre_of_any_goal(dmp):
    rng = np.random.default_rng(2)
    starts, goals = rng.uniform(-0.5, 0.5, (500, 3)), rng.uniform(-0.5, 0.5, (500, 3))
    final = dmp.rollout(starts, goals).y[:, -1]
    assert np.linalg.norm(final - goals, axis=1).max() < 1e-5


def test_a_demonstration_that_stops_abruptly_still_ends_on_its_goal_and_stays():
    """Like the LASA demonstrations: full speed up to the last sample."""
    t = np.linspace(0.0, 2.0, 500)
    y = np.column_stack([30 * np.sin(1.2 * t), 40 * t - 5 * t**2])  # mm, still moving at t = 2
    dmp = DMP(2, n_basis=100).fit([(t, y)])
    assert dmp.fit_rmse < 0.1
    rollout = dmp.rollout(y[0], y[-1], tau=2.0, duration=4.0, dt=0.004)
    after = np.linalg.norm(rollout.y[rollout.t >= 2.0] - y[-1], axis=1)
    assert after.max() < 0.1 and after[-1] < 0.01
    goals = y[-1] + np.random.default_rng(3).normal(0, 20, (50, 2))
    batch = dmp.rollout(np.tile(y[0], (50, 1)), goals, tau=2.0, duration=4.0, dt=0.004)
    assert np.linalg.norm(batch.y[:, batch.t >= 2.0] - goals[:, None], axis=2).max() < 0.1
    assert np.linalg.norm(batch.y[:, -1] - goals, axis=1).max() < 0.01


# -- τ and batches -----------------------------------------------------------------------------
def test_tau_changes_the_duration_not_the_path(dmp, demo):
    _, y = demo
    normal = dmp.rollout(y[0], y[-1], tau=1.0)
    slow = dmp.rollout(y[0], y[-1], tau=2.0)
    assert slow.t[-1] == pytest.approx(2 * normal.t[-1])
    assert slow.y[::2] == pytest.approx(normal.y, abs=1e-12)
    assert slow.yd[::2] == pytest.approx(normal.yd / 2, abs=1e-12)
    # Any other τ: the same path at the same normalised times, exactly.
    fast = dmp.rollout(y[0], y[-1], tau=0.63, dt=0.0063, duration=0.63)
    reference = dmp.rollout(y[0], y[-1], tau=1.0, dt=0.01, duration=1.0)
    assert fast.y == pytest.approx(reference.y, abs=1e-12)


def test_a_batch_equals_a_loop_of_single_rollouts(dmp):
    rng = np.random.default_rng(2)
    starts, goals = rng.normal(0, 0.2, (7, 3)), rng.normal(0, 0.2, (7, 3))
    batch = dmp.rollout(starts, goals, tau=0.8)
    assert batch.y.shape == (7, len(batch.t), 3)
    for k in range(7):
        single = dmp.rollout(starts[k], goals[k], tau=0.8)
        for field in ("y", "yd", "ydd"):
            assert getattr(batch, field)[k] == pytest.approx(getattr(single, field), abs=1e-12)
    shared = dmp.rollout(starts, goals[0])  # one goal for many starts broadcasts
    assert shared.y[:, -1] == pytest.approx(np.tile(goals[0], (7, 1)), abs=1e-5)


def test_each_movement_of_a_batch_may_have_its_own_tau(dmp):
    rng = np.random.default_rng(4)
    starts, goals = rng.normal(0, 0.2, (4, 3)), rng.normal(0, 0.2, (4, 3))
    taus = np.array([0.5, 1.0, 1.7, 0.8])
    batch = dmp.rollout(starts, goals, tau=taus, dt=0.01)
    assert batch.t[-1] == pytest.approx(1.3 * 1.7)  # long enough for the slowest
    for k, tau in enumerate(taus):
        single = dmp.rollout(starts[k], goals[k], tau=tau, dt=0.01, duration=batch.t[-1])
        assert batch.y[k] == pytest.approx(single.y, abs=1e-12)
        assert batch.ydd[k] == pytest.approx(single.ydd, abs=1e-9)
        after = np.linalg.norm(batch.y[k, batch.t >= tau] - goals[k], axis=1)
        assert after.max() < 1e-4
    with pytest.raises(Exception, match="one per movement"):
        dmp.rollout(starts, goals, tau=[1.0, 2.0])


def test_the_shared_integration_equals_stepping_every_movement(dmp):
    """Without couplings rollouts superpose shared responses; a zero coupling forces the step loop."""
    rng = np.random.default_rng(3)
    starts, goals = rng.normal(0, 0.2, (4, 3)), rng.normal(0, 0.2, (4, 3))

    def no_force(t, y, z):
        return torch.zeros_like(y)

    for tau, dt in [(1.0, 0.01), (0.5, 0.02), (1.7, 0.005), (np.array([0.6, 1.0, 1.3, 2.0]), 0.01)]:
        shared = dmp.rollout(starts, goals, tau=tau, dt=dt)
        stepped = dmp.rollout(starts, goals, tau=tau, dt=dt, coupling_force=no_force)
        for field in ("y", "yd", "ydd"):
            assert getattr(shared, field) == pytest.approx(getattr(stepped, field), abs=1e-9)


# -- coupling terms ----------------------------------------------------------------------------
def test_a_constant_coupling_force_shifts_the_rest_point_by_c_over_the_stiffness():
    spring = DMP(1)  # no forcing term learned: a critically damped spring
    c = 3.0

    def push(t, y, z):
        return torch.full_like(y, c)

    rollout = spring.rollout(np.zeros(1), np.zeros(1), tau=1.0, duration=3.0, coupling_force=push)
    assert rollout.y[-1, 0] == pytest.approx(c / (spring.alpha_z * spring.beta_z), rel=1e-4)
    assert np.all(np.diff(rollout.y[:, 0]) >= -1e-12)  # critically damped: no overshoot


def test_a_transient_coupling_force_bends_the_path_and_the_goal_is_still_reached(dmp, demo):
    _, y = demo

    def sideways(t, y_now, z):
        force = torch.zeros_like(y_now)
        force[:, 1:2] = torch.where(t < 0.4, 20.0, 0.0)
        return force

    free = dmp.rollout(y[0], y[-1])
    bent = dmp.rollout(y[0], y[-1], coupling_force=sideways)
    assert (bent.y[:, 1] - free.y[:, 1]).max() > 0.02  # pushed toward +y ...
    assert bent.y[:, [0, 2]] == pytest.approx(free.y[:, [0, 2]], abs=1e-12)  # ... only in y
    assert np.linalg.norm(bent.y[-1] - y[-1]) < 1e-3


def test_a_phase_coupling_that_stops_the_canonical_system_freezes_the_forcing_term(dmp, demo):
    _, y = demo

    def hold(t, x, y_now):
        return dmp.alpha_x * x  # τẋ = −α_x x + α_x x = 0

    held = dmp.rollout(y[0], y[-1], duration=4.0, coupling_phase=hold)
    # x stays 1, so f = s Σψ(1)w / Σψ(1) is constant and the spring rests at g + f / (α_z β_z).
    forcing = dmp.forcing(np.ones(1))[0] * dmp.scale(y[0], y[-1])
    assert held.y[-1] == pytest.approx(y[-1] + forcing / (dmp.alpha_z * dmp.beta_z), abs=1e-6)
    # A phase slowed to half speed delays the movement: less progress at t = τ / 2.
    slowed = dmp.rollout(y[0], y[-1], coupling_phase=lambda t, x, _: 0.5 * dmp.alpha_x * x)
    free = dmp.rollout(y[0], y[-1])

    def progress(r):
        return np.dot(r.y[50] - y[0], y[-1] - y[0]) / np.dot(y[-1] - y[0], y[-1] - y[0])

    assert progress(slowed) < progress(free) - 0.1


# -- against movement_primitives ---------------------------------------------------------------
def test_reproduction_and_goal_error_at_least_as_good_as_movement_primitives(demo):
    their_module = pytest.importorskip("movement_primitives.dmp")
    t, y = demo
    ours = DMP(3, n_basis=50).fit([demo])
    theirs = their_module.DMP(3, execution_time=1.0, dt=0.01, n_weights_per_dim=50)
    theirs.imitate(t, y)
    theirs.configure(start_y=y[0], goal_y=y[-1])
    their_rmse = rmse(theirs.open_loop()[1][: len(y)], y)
    assert ours.fit_rmse <= their_rmse
    goals = y[-1] + np.random.default_rng(6).normal(0, 0.03, (20, 3))
    their_ends = []
    for goal in goals:
        theirs.configure(start_y=y[0], goal_y=goal)
        their_ends.append(theirs.open_loop()[1][-1])
    our_ends = ours.rollout(y[0], goals).y[:, -1]
    assert np.linalg.norm(our_ends - goals, axis=1).max() <= np.linalg.norm(np.array(their_ends) - goals, axis=1).max()


# -- devices -----------------------------------------------------------------------------------
def test_coupled_rollouts_run_on_cuda_when_there_is_one_else_on_the_cpu(dmp):
    assert dmp.device == torch.device("cuda" if torch.cuda.is_available() else "cpu")
    assert DMP(3, device="cpu").device == torch.device("cpu")  # a device asked for is kept


DEVICES = ["cpu"] + (["cuda"] if torch.cuda.is_available() else [])


@pytest.mark.parametrize("device", DEVICES)
def test_coupled_rollouts_on_each_device_equal_the_closed_form_rollouts(dmp, demo, device):
    # A zero coupling force takes the stepped (torch) path on the device; it must give the
    # closed-form superposition of the uncoupled rollout, for a batch of starts.
    _, y = demo
    starts = y[0] + np.random.default_rng(5).normal(0, 0.1, (16, 3))
    on_device = DMP.from_arrays(dmp.to_arrays())
    on_device.device = torch.device(device)
    seen: list[torch.device] = []

    def no_force(t, y_now, z):
        seen.append(y_now.device)
        return torch.zeros_like(y_now)

    stepped = on_device.rollout(starts, y[-1], coupling_force=no_force).y
    assert seen and {d.type for d in seen} == {device}  # the coupling ran on the device asked for
    assert stepped.shape == (16, 131, 3)
    assert stepped == pytest.approx(dmp.rollout(starts, y[-1]).y, abs=1e-9)
