"""The DMP of vslsp.dmp: learning from demonstrations, reproduction, generalisation, files.

The demonstrations are smooth reaches: a minimum-jerk move from start to goal plus a lift that
rises and falls back (zero velocity at both ends), like a hand going over the table.
"""

import numpy as np
import pytest
import torch

from vslsp.dmp import DMP, Rollout
from vslsp.errors import InputError

LIFT = np.array([0.05, 0.0, 0.1])  # the lift's peak offset (m): sideways in x, up in z


def reach(start=(0.0, 0.0, 0.0), goal=(0.3, -0.2, 0.0), duration=1.0, samples=101):
    """A demonstration (t (T,), y (T, 3)): minimum-jerk start → goal with a lift on the way."""
    t = np.linspace(0.0, duration, samples)
    u = t / duration
    progress = 10 * u**3 - 15 * u**4 + 6 * u**5
    start, goal = np.asarray(start, dtype=float), np.asarray(goal, dtype=float)
    lift = np.sin(np.pi * u) ** 2
    return t, start + progress[:, None] * (goal - start) + lift[:, None] * LIFT * np.linalg.norm(goal - start) / 0.36


def rmse(a, b):
    return float(np.sqrt(np.mean(np.sum((a - b) ** 2, axis=-1))))


@pytest.fixture(scope="module")
def demo():
    return reach()


@pytest.fixture(scope="module")
def dmp(demo):
    return DMP(3).fit([demo])


# -- learning and reproduction ---------------------------------------------------------------
def test_fit_reproduces_a_smooth_demonstration_within_a_millimetre(dmp, demo):
    t, y = demo
    rollout = dmp.rollout(y[0], y[-1], tau=t[-1], dt=t[1] - t[0], duration=t[-1])
    assert rollout.y.shape == y.shape
    assert rmse(rollout.y, y) < 1e-3
    assert dmp.fit_rmse == pytest.approx(rmse(rollout.y, y))
    assert (dmp.n_demos, dmp.tau, dmp.dt) == (1, pytest.approx(1.0), pytest.approx(0.01))


def test_rollout_returns_time_position_velocity_and_acceleration_that_agree(dmp, demo):
    t, y = demo
    rollout = dmp.rollout(y[0], y[-1])
    assert isinstance(rollout, Rollout)
    assert rollout.t == pytest.approx(np.arange(131) * 0.01)  # 1.3 τ by default
    assert rollout.y.shape == rollout.yd.shape == rollout.ydd.shape == (131, 3)
    assert rollout.y[0] == pytest.approx(y[0], abs=1e-12)
    assert np.abs(rollout.yd[0]).max() < 0.05  # starts at rest (one-sided difference)
    # ÿ is the model's own acceleration: integrated, it gives back the velocity.
    integral = np.concatenate([np.zeros((1, 3)), np.cumsum((rollout.ydd[1:] + rollout.ydd[:-1]) / 2 * 0.01, axis=0)])
    assert integral == pytest.approx(rollout.yd, abs=0.03 * np.abs(rollout.yd).max())


def test_rollouts_converge_to_new_goals_within_a_millimetre(dmp):
    rng = np.random.default_rng(1)
    starts, goals = rng.uniform(-0.2, 0.2, (50, 3)), rng.uniform(-0.3, 0.3, (50, 3))
    final = dmp.rollout(starts, goals).y[:, -1]
    assert np.linalg.norm(final - goals, axis=1).max() < 1e-3
    settled = dmp.rollout(starts, goals, duration=2.0).y[:, -1]
    assert np.linalg.norm(settled - goals, axis=1).max() < 1e-5


def test_tau_changes_the_duration_not_the_path(dmp, demo):
    _, y = demo
    normal = dmp.rollout(y[0], y[-1], tau=1.0)
    slow = dmp.rollout(y[0], y[-1], tau=2.0)
    assert slow.t[-1] == pytest.approx(2 * normal.t[-1])
    # Same Euler steps in phase: every second sample of the slow one is the normal one.
    assert slow.y[::2] == pytest.approx(normal.y, abs=1e-12)
    assert np.abs(slow.yd).max() == pytest.approx(np.abs(normal.yd).max() / 2, rel=0.02)
    # Any other τ: resampled onto the same phase, the path is the same up to the Euler steps'
    # discretisation (their size in phase, h/τ, differs a little).
    fine = dmp.rollout(y[0], y[-1], tau=1.0, dt=0.001)
    fast = dmp.rollout(y[0], y[-1], tau=0.63, dt=0.001)
    assert fast.t[-1] == pytest.approx(1.3 * 0.63, abs=0.001)
    phase = fine.t / fine.t[-1]
    resampled = np.column_stack([np.interp(phase, fast.t / fast.t[-1], fast.y[:, k]) for k in range(3)])
    assert np.abs(resampled - fine.y).max() < 3e-4


def test_a_batch_equals_a_loop_of_single_rollouts(dmp):
    rng = np.random.default_rng(2)
    starts, goals = rng.normal(0, 0.2, (7, 3)), rng.normal(0, 0.2, (7, 3))
    batch = dmp.rollout(starts, goals, tau=0.8)
    assert batch.y.shape == (7, len(batch.t), 3)
    for k in range(7):
        single = dmp.rollout(starts[k], goals[k], tau=0.8)
        for field in ("y", "yd", "ydd"):
            assert getattr(batch, field)[k] == pytest.approx(getattr(single, field), abs=1e-12)
    # One goal for many starts broadcasts.
    shared = dmp.rollout(starts, goals[0])
    assert shared.y[:, -1] == pytest.approx(np.tile(goals[0], (7, 1)), abs=1e-3)


def test_the_shared_integration_equals_stepping_every_movement(dmp):
    """Without couplings rollouts superpose one integration; a zero coupling forces the step loop."""
    rng = np.random.default_rng(3)
    starts, goals = rng.normal(0, 0.2, (4, 3)), rng.normal(0, 0.2, (4, 3))
    def no_force(t, y, z):
        return torch.zeros_like(y)
    for tau, dt in [(1.0, 0.01), (0.5, 0.02), (1.7, 0.005)]:
        shared = dmp.rollout(starts, goals, tau=tau, dt=dt)
        stepped = dmp.rollout(starts, goals, tau=tau, dt=dt, coupling_force=no_force)
        assert shared.y == pytest.approx(stepped.y, abs=1e-9)
        assert shared.ydd == pytest.approx(stepped.ydd, abs=1e-9)


def test_several_demonstrations_with_their_own_starts_goals_and_durations():
    demos = [
        reach((0.0, 0.0, 0.0), (0.3, -0.2, 0.0), duration=1.0, samples=101),
        reach((0.1, 0.05, 0.02), (0.25, -0.05, 0.02), duration=0.7, samples=141),
        reach((-0.2, 0.1, -0.05), (0.25, -0.2, -0.05), duration=1.6, samples=81),
    ]
    dmp = DMP(3).fit(demos)
    assert dmp.n_demos == 3
    assert dmp.tau == pytest.approx(np.mean([1.0, 0.7, 1.6]))
    assert dmp.fit_rmse < 1e-3
    for t, y in demos:
        rollout = dmp.rollout(y[0], y[-1], tau=t[-1], dt=t[1] - t[0], duration=t[-1])
        assert rmse(rollout.y, y) < 1e-3


# -- generalisation: goals near the start and behind it ----------------------------------------
def test_a_goal_at_the_start_holds_still_and_a_near_one_shrinks_the_movement(dmp, demo):
    _, y = demo
    assert dmp.rollout(y[0], y[0]).y == pytest.approx(np.tile(y[0], (131, 1)), abs=1e-15)
    # The whole movement scales with ‖g − y0‖: no division by a vanishing amplitude.
    direction = (y[-1] - y[0]) / np.linalg.norm(y[-1] - y[0])
    sizes = [1e-2, 1e-4, 1e-7]
    deviations = [np.abs(dmp.rollout(y[0], y[0] + d * direction).y - y[0]).max() for d in sizes]
    assert np.all(np.isfinite(deviations))
    ratios = np.array(deviations) / sizes
    assert ratios == pytest.approx(ratios[0], rel=1e-6)
    assert ratios[0] < 2.0


def test_a_goal_on_the_other_side_keeps_the_lift_and_does_not_blow_up(dmp, demo):
    """The paper's factor (g − y0) would flip the lift's sign per dimension (and has none for z,
    whose start and goal are level); the scalar ‖g − y0‖ / A keeps the forcing's direction.
    The price: the forcing that held the spring back now adds to it, so the hand overshoots
    the goal (about 1.6 × the amplitude from the start at worst) before it settles."""
    _, y = demo
    behind = y[0] - (y[-1] - y[0])
    rollout = dmp.rollout(y[0], behind).y
    assert np.linalg.norm(rollout[-1] - behind) < 1e-3
    assert rollout[:, 2].max() == pytest.approx(y[:, 2].max(), rel=0.05)  # still lifts up ...
    assert rollout[:, 2].min() > y[0, 2] - 1e-3  # ... and never dips below the start height
    amplitude = np.linalg.norm(behind - y[0])
    assert np.linalg.norm(rollout - y[0], axis=1).max() < 2.0 * amplitude


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
        force[:, 1] = 20.0 if float(t) < 0.4 else 0.0
        return force
    free = dmp.rollout(y[0], y[-1])
    bent = dmp.rollout(y[0], y[-1], coupling_force=sideways)
    assert (bent.y[:, 1] - free.y[:, 1]).max() > 0.02  # pushed toward +y ...
    assert bent.y[:, [0, 2]] == pytest.approx(free.y[:, [0, 2]], abs=1e-12)  # ... only in y
    assert np.linalg.norm(bent.y[-1] - y[-1]) < 1e-3


def test_a_phase_coupling_that_stops_the_canonical_system_freezes_the_forcing_term(dmp, demo):
    _, y = demo
    def hold(t, x, _):
        return dmp.alpha_x * x  # τẋ = −α_x x + α_x x = 0
    held = dmp.rollout(y[0], y[-1], duration=4.0, coupling_phase=hold)
    # x stays 1, so f = Σψ(1)w / Σψ(1) · s is constant and the spring rests at g + f / (α_z β_z).
    psi = dmp._basis(np.ones(1))
    forcing = (psi @ dmp.weights)[0] / psi.sum() * np.linalg.norm(y[-1] - y[0]) / dmp.amplitude
    assert held.y[-1] == pytest.approx(y[-1] + forcing / (dmp.alpha_z * dmp.beta_z), abs=1e-6)
    # A phase slowed to half speed delays the movement: less progress at t = τ / 2.
    slowed = dmp.rollout(y[0], y[-1], coupling_phase=lambda t, x, _: 0.5 * dmp.alpha_x * x)
    free = dmp.rollout(y[0], y[-1])
    progress = lambda r: np.dot(r.y[50] - y[0], y[-1] - y[0]) / np.dot(y[-1] - y[0], y[-1] - y[0])
    assert progress(slowed) < progress(free) - 0.1


# -- bad input ---------------------------------------------------------------------------------
@pytest.mark.parametrize("demos", [
    [],
    [(np.linspace(0, 1, 10), np.zeros((10, 2)))],  # wrong dimension
    [(np.linspace(0, 1, 9), np.zeros((10, 3)))],  # t and y disagree
    [(np.linspace(0, 1, 3), np.zeros((3, 3)))],  # too short
])
def test_fit_rejects_malformed_demonstrations(demos):
    with pytest.raises(InputError, match="demonstration"):
        DMP(3).fit(demos)


def test_rollout_rejects_wrong_dimensions_and_non_positive_times(dmp):
    with pytest.raises(InputError, match="3 dimensions"):
        dmp.rollout(np.zeros(2), np.ones(2))
    with pytest.raises(InputError, match="positive"):
        dmp.rollout(np.zeros(3), np.ones(3), tau=0.0)
    with pytest.raises(InputError, match="shorter than one sample"):
        dmp.rollout(np.zeros(3), np.ones(3), duration=0.001)
    with pytest.raises(InputError):
        DMP(0)


# -- files -------------------------------------------------------------------------------------
def test_save_and_load_give_identical_rollouts(dmp, demo, tmp_path):
    _, y = demo
    dmp.save(tmp_path / "reach.npz")
    loaded = DMP.load(tmp_path / "reach.npz")
    for name in ("n_dims", "n_basis", "alpha_z", "beta_z", "alpha_x", "amplitude", "tau", "dt", "fit_rmse", "n_demos"):
        assert getattr(loaded, name) == getattr(dmp, name)
    starts = y[0] + np.random.default_rng(4).normal(0, 0.1, (5, 3))
    assert np.array_equal(loaded.rollout(starts, y[-1]).y, dmp.rollout(starts, y[-1]).y)
    with np.load(tmp_path / "reach.npz", allow_pickle=False) as data:  # no pickle needed
        assert set(data.files) == {"meta", "weights"}


def test_a_corrupt_file_is_an_input_error(tmp_path):
    path = tmp_path / "broken.npz"
    path.write_bytes(b"PK\x03\x04 this is not a zip archive")
    with pytest.raises(InputError, match="broken.npz"):
        DMP.load(path)


def test_a_foreign_npz_is_an_input_error_that_says_what_to_do(dmp, tmp_path):
    np.savez(tmp_path / "image.npz", pixels=np.zeros((4, 4)))
    with pytest.raises(InputError, match="not a vslsp DMP.*vslsp teach"):
        DMP.load(tmp_path / "image.npz")
    arrays = dmp.to_arrays()
    np.savez(tmp_path / "other.npz", meta=np.array('{"format": "someone-else"}'), weights=arrays["weights"])
    with pytest.raises(InputError, match="not a vslsp DMP"):
        DMP.load(tmp_path / "other.npz")
    np.savez(tmp_path / "shape.npz", meta=arrays["meta"], weights=np.zeros((3, 3)))
    with pytest.raises(InputError, match="weights"):
        DMP.load(tmp_path / "shape.npz")
    np.savez(tmp_path / "pickled.npz", meta=np.array([{"format": "vslsp-dmp"}], dtype=object))
    with pytest.raises(InputError, match="pickled.npz"):
        DMP.load(tmp_path / "pickled.npz")


def test_a_missing_file_is_an_input_error(tmp_path):
    with pytest.raises(InputError, match="no DMP file .*missing.npz.*vslsp teach"):
        DMP.load(tmp_path / "missing.npz")


# -- devices -----------------------------------------------------------------------------------
def test_rollouts_run_on_the_cpu_by_default_without_cuda(dmp):
    if not torch.cuda.is_available():
        assert dmp.device == torch.device("cpu")


@pytest.mark.skipif(not torch.cuda.is_available(), reason="no CUDA device")
def test_cuda_rollouts_equal_cpu_rollouts(dmp, demo):
    _, y = demo
    starts = y[0] + np.random.default_rng(5).normal(0, 0.1, (16, 3))
    on_gpu = DMP(3, device="cuda")
    on_gpu.weights, on_gpu.amplitude, on_gpu.tau, on_gpu.dt = dmp.weights, dmp.amplitude, dmp.tau, dmp.dt
    on_cpu = DMP(3, device="cpu")
    on_cpu.weights, on_cpu.amplitude, on_cpu.tau, on_cpu.dt = dmp.weights, dmp.amplitude, dmp.tau, dmp.dt
    assert on_gpu.rollout(starts, y[-1]).y == pytest.approx(on_cpu.rollout(starts, y[-1]).y, abs=1e-9)
    def no_force(t, y_now, z):
        return torch.zeros_like(y_now)
    stepped = on_gpu.rollout(starts, y[-1], coupling_force=no_force).y
    assert stepped == pytest.approx(on_cpu.rollout(starts, y[-1]).y, abs=1e-9)
