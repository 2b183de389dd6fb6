"""The discrete DMP: learning from demonstrations, batched rollouts, files.

Paper section "Learning Sensorimotor Skills using Imitation Learning". The formulation (a
forcing term gated to vanish at τ, a terminal condition on its response, the scale-free
amplitude factor) is written down in :mod:`vslsp.dmp`; the exact integration in
:mod:`vslsp.dmp._system`; the canonical system, gate and amplitude factor in
:mod:`vslsp.dmp._forcing`.
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np
import torch

from vslsp.dmp import _forcing, _system
from vslsp.dmp._validation import check_demonstrations, check_points, check_times
from vslsp.errors import InputError
from vslsp.files import load_npz, shown
from vslsp.outputs import atomic_file

FORMAT = "vslsp-dmp"
MAX_FILE_BYTES = 64_000_000  # a DMP file's arrays, decoded (1000 basis functions x 3 dimensions need 24 kB)
VERSION = 2
Coupling = Callable[[torch.Tensor, torch.Tensor, torch.Tensor], torch.Tensor]


@dataclass(frozen=True)
class Rollout:
    """A reproduced movement.

    Attributes
    ----------
    t : array, shape (T,)
        Sample times (s), every ``dt`` from 0.
    y, yd, ydd : array, shape (T, D), or (B, T, D) when batched
        Position, velocity and acceleration at the sample times.
    """

    t: np.ndarray
    y: np.ndarray
    yd: np.ndarray
    ydd: np.ndarray


def _default_device() -> torch.device:
    return torch.device("cuda") if torch.cuda.is_available() else torch.device("cpu")


@lru_cache(maxsize=8)
def _basis_grid(n_basis: int, alpha_x: float, alpha_z: float) -> tuple[np.ndarray, np.ndarray]:
    """The gated basis held on the grid, (N, n_basis), and the spring's response to each, (N + 1, 2, n_basis)."""
    centres, widths = _forcing.centres_and_widths(n_basis, alpha_x)
    inputs = _forcing.basis(_forcing.grid_phases(_system.STEPS, alpha_x), centres, widths, alpha_x)
    states = _system.grid_responses(inputs, alpha_z / 2.0)
    inputs.flags.writeable = states.flags.writeable = False
    return inputs, states


class DMP:
    """A discrete DMP over ``n_dims`` dimensions with ``n_basis`` Gaussian basis functions.

    Parameters
    ----------
    n_dims : int
        Dimensions D of the movement.
    n_basis : int, optional (default: 50)
        Basis functions per dimension, spaced evenly in time over [0, τ).
    alpha_z : float, optional (default: 25)
        Spring gain α_z; β_z = α_z / 4 (critically damped).
    alpha_x : float, optional (default: 4.6)
        Canonical system gain: the phase is exp(−α_x) = 0.01 at τ.
    regularization : float, optional (default: 1e-6)
        Ridge penalty on the weights, relative to the mean squared response of a weight.
    device : str or torch.device, optional
        Where coupled rollouts run (default: CUDA when available); uncoupled ones are
        closed-form numpy broadcasts.

    Attributes
    ----------
    weights : array, shape (n_basis, n_dims)
        Forcing-term weights.
    amplitude : float
        A, the demonstrations' mean start-goal distance.
    extent : float
        E, the demonstrations' mean largest distance from their start-goal segment.
    tau, dt : float
        The demonstrations' mean duration and sample period (s): the rollout defaults.
    fit_rmse : float
        RMS distance between the demonstrations and their reproductions.
    """

    def __init__(
        self,
        n_dims: int,
        n_basis: int = 50,
        alpha_z: float = 25.0,
        alpha_x: float = 4.6,
        regularization: float = 1e-6,
        device: str | torch.device | None = None,
    ) -> None:
        numbers = (alpha_z, alpha_x, regularization)
        if (
            not isinstance(n_dims, int | np.integer)
            or not isinstance(n_basis, int | np.integer)
            or n_dims < 1
            or n_basis < 2
        ):
            raise InputError(f"a DMP needs integers n_dims >= 1 and n_basis >= 2, got {n_dims}, {n_basis}")
        if not all(np.isfinite(numbers)) or alpha_z <= 0 or alpha_x <= 0 or regularization < 0:
            raise InputError(f"alpha_z and alpha_x must be positive and regularization >= 0, got {numbers}")
        self.n_dims, self.n_basis = int(n_dims), int(n_basis)
        self.alpha_z, self.beta_z, self.alpha_x = float(alpha_z), float(alpha_z) / 4.0, float(alpha_x)
        self.regularization = float(regularization)
        self.device = torch.device(device) if device is not None else _default_device()
        self.centers, self.widths = _forcing.centres_and_widths(self.n_basis, self.alpha_x)
        self.weights = np.zeros((self.n_basis, self.n_dims))
        self.amplitude, self.extent = 1.0, 0.0
        self.tau, self.dt = 1.0, 0.01
        self.fit_rmse = float("nan")
        self.n_demos = 0

    @property
    def omega(self) -> float:
        """The spring's natural frequency in normalised time, α_z / 2."""
        return self.alpha_z / 2.0

    def scale(self, y0: np.ndarray, goal: np.ndarray) -> np.ndarray:
        """The amplitude factor s (...) of movements from ``y0`` to ``goal`` (..., D)."""
        distance = np.linalg.norm(np.asarray(goal, dtype=np.float64) - np.asarray(y0, dtype=np.float64), axis=-1)
        return _forcing.amplitude_factor(distance, self.amplitude, self.extent)

    def forcing(self, x: np.ndarray) -> np.ndarray:
        """The unscaled forcing term γ(x) Σψw / Σψ: (..., D) at phases x (...)."""
        return _forcing.basis(x, self.centers, self.widths, self.alpha_x) @ self.weights

    # -- learning ---------------------------------------------------------------------------
    def fit(self, demos: list[tuple[np.ndarray, np.ndarray]]) -> DMP:
        """Learn the weights from demonstrations.

        Parameters
        ----------
        demos : list of (t, y)
            Each with times t, shape (T,), strictly increasing, and positions y, shape (T, D);
            every demonstration has its own start, goal, duration and sample count.

        Returns
        -------
        DMP
            ``self``, fitted: the weights minimise the squared distance between the
            demonstrations and their reproductions (ridge-regularised), subject to the forcing
            term's response ending at rest at u = 1.
        """
        checked = check_demonstrations(demos, self.n_dims)
        self.amplitude = float(np.mean([np.linalg.norm(y[-1] - y[0]) for _, y in checked]))
        self.extent = float(np.mean([_forcing.chord_extent(y) for _, y in checked]))
        self.tau = float(np.mean([t[-1] for t, _ in checked]))
        self.dt = float(np.mean([np.mean(np.diff(t)) for t, _ in checked]))
        inputs, states = _basis_grid(self.n_basis, self.alpha_x, self.alpha_z)
        # The forcing term's response at u = 1, position and rate, must be zero: the weights
        # live in the null space of those two rows.
        _, _, vt = np.linalg.svd(states[-1])
        null = vt[2:].T  # (n_basis, n_basis − 2), orthonormal columns
        rows, targets = [], []
        for t, y in checked:
            u = t / t[-1]
            response = _system.at_phases(states, inputs, u, self.omega)[:, 0, :]  # (T, n_basis)
            free = _system.free_response(u, self.omega)[:, :1] * (y[0] - y[-1])
            weight = 1.0 / np.sqrt(len(t))  # every demonstration counts the same
            rows.append(self.scale(y[0], y[-1]) * weight * response)
            targets.append(weight * (y - y[-1] - free))
        design = np.vstack(rows) @ null
        gram = design.T @ design
        ridge = self.regularization * np.trace(gram) / len(gram)
        self.weights = null @ np.linalg.solve(gram + ridge * np.eye(len(gram)), design.T @ np.vstack(targets))
        self.n_demos = len(checked)
        errors = [self._positions(y[0], y[-1], t / t[-1]) - y for t, y in checked]
        self.fit_rmse = float(np.sqrt(np.mean(np.concatenate([np.sum(e**2, axis=1) for e in errors]))))
        return self

    def _positions(self, y0: np.ndarray, goal: np.ndarray, u: np.ndarray) -> np.ndarray:
        """Positions (T, D) of one uncoupled movement at normalised times u (T,)."""
        inputs, states = self._forcing_grid()
        forced = _system.at_phases(states, inputs, u, self.omega)[:, 0, :]
        free = _system.free_response(u, self.omega)[:, :1] * (y0 - goal)
        return goal + free + self.scale(y0, goal) * forced

    def _forcing_grid(self) -> tuple[np.ndarray, np.ndarray]:
        """The learned forcing term held on the grid, (N, D), and the spring's response to it, (N + 1, 2, D)."""
        inputs, states = _basis_grid(self.n_basis, self.alpha_x, self.alpha_z)
        return inputs @ self.weights, states @ self.weights

    # -- reproduction -------------------------------------------------------------------------
    def rollout(
        self,
        y0: np.ndarray,
        goal: np.ndarray,
        tau: float | np.ndarray | None = None,
        dt: float | None = None,
        duration: float | None = None,
        coupling_force: Coupling | None = None,
        coupling_phase: Coupling | None = None,
    ) -> Rollout:
        """Reproduce the movement from ``y0`` to ``goal``.

        Parameters
        ----------
        y0, goal : array, shape (D,) or (B, D)
            Start and goal; a single one broadcasts over the batch.
        tau : float or array, shape (B,), optional
            Each movement's duration (s; default: the demonstrations'). The forcing term
            vanishes at τ and its response has come to rest: from then on the hand is within
            P(1) ‖g − y0‖ = 5e-5 ‖g − y0‖ of the goal (the free spring's remainder).
        dt : float, optional
            Sample period (s; default: the demonstrations').
        duration : float, optional
            How long to roll out (s; default 1.3 times the longest τ).
        coupling_force : callable, optional
            ``(t (B, 1), y (B, D), z (B, D)) -> (B, D)`` tensor added to the forcing term, C_f
            in τ ż = α_z (β_z (g − y) − z) + f + C_f, held over each 1/1000 of τ.
        coupling_phase : callable, optional
            ``(t (B, 1), x (B, 1), y (B, D)) -> (B, 1)`` tensor C_c in τ ẋ = −α_x x + C_c.

        Returns
        -------
        Rollout
            ``t`` (T,) and ``y``, ``yd``, ``ydd`` of shape (T, D), or (B, T, D) when batched.
        """
        y0, goal, batched = check_points(y0, goal, self.n_dims)
        taus, dt, duration = check_times(
            self.tau if tau is None else tau, self.dt if dt is None else dt, duration, len(y0)
        )
        t = np.arange(int(np.floor(duration / dt + 1e-9)) + 1) * dt
        if coupling_force is None and coupling_phase is None:
            y, yd, ydd = self._superpose(y0, goal, taus, t)
        else:
            y, yd, ydd = self._step(y0, goal, taus, t, coupling_force, coupling_phase)
        if not batched:
            return Rollout(t=t, y=y[0], yd=yd[0], ydd=ydd[0])
        return Rollout(t=t, y=y, yd=yd, ydd=ydd)

    def _superpose(
        self, y0: np.ndarray, goal: np.ndarray, taus: np.ndarray, t: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """y, ẏ, ÿ (B, T, D) of uncoupled movements: e = P(u) e0 + s F(u), evaluated exactly.

        P is the free spring's response and F the learned forcing term's, both functions of
        u = t / τ alone, so a batch sharing τ needs them once and each output is one
        broadcast ``p e0 + s q`` over the batch (numpy: memory-bound, no gain from torch).
        """
        inputs, states = self._forcing_grid()
        tau = taus[:1, None] if np.all(taus == taus[0]) else taus[:, None]  # (B', 1)
        u = t[None, :] / tau  # (B', T)
        free = _system.free_response(u, self.omega)  # (B', T, 2)
        forced = _system.at_phases(states, inputs, u, self.omega)  # (B', T, 2, D)
        held = _system.held_input(inputs, u)  # (B', T, D)
        w2, w = self.omega**2, 2.0 * self.omega
        parts = [  # (coefficient of e0 (B', T), of s (B', T, D)) for y − g, ẏ and ÿ
            (free[..., 0], forced[..., 0, :]),
            (free[..., 1] / tau, forced[..., 1, :] / tau[..., None]),
            (
                (-w2 * free[..., 0] - w * free[..., 1]) / tau**2,
                (-w2 * forced[..., 0, :] - w * forced[..., 1, :] + held) / tau[..., None] ** 2,
            ),
        ]
        e0, s = (y0 - goal)[:, None, :], self.scale(y0, goal)[:, None, None]
        y, yd, ydd = (p[..., None] * e0 + s * q for p, q in parts)
        y += goal[:, None, :]
        return y, yd, ydd

    def _step(
        self,
        y0: np.ndarray,
        goal: np.ndarray,
        taus: np.ndarray,
        t: np.ndarray,
        coupling_force: Coupling | None,
        coupling_phase: Coupling | None,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """y, ẏ, ÿ (B, T, D) of coupled movements, stepped 1/N of normalised time at a time.

        The couplings and the phase are held over each step; the spring is integrated exactly
        (as in :meth:`_superpose`, which this equals when the couplings are zero).
        """
        options: dict[str, Any] = {"dtype": torch.float64, "device": self.device}
        n = _system.STEPS
        steps = int(np.ceil(t[-1] / taus.min() * n)) + 1
        phi, gamma = (torch.as_tensor(a, **options) for a in _system.step_matrices(np.array(1.0 / n), self.omega))
        weights = torch.as_tensor(self.weights, **options)
        centers, widths = torch.as_tensor(self.centers, **options), torch.as_tensor(self.widths, **options)
        g = torch.as_tensor(goal, **options)
        tau = torch.as_tensor(taus, **options)[:, None]
        s = torch.as_tensor(self.scale(y0, goal), **options)[:, None]
        e, v = torch.as_tensor(y0 - goal, **options), torch.zeros_like(g)
        x = torch.ones((len(y0), 1), **options)
        full, half = np.exp(-self.alpha_x / n), np.exp(-self.alpha_x / (2 * n))
        states, inputs = [torch.stack([e, v], dim=1)], []
        for j in range(steps):
            now = j / n * tau
            drive = coupling_phase(now, x, g + e) if coupling_phase is not None else torch.zeros_like(x)
            middle = x * half + (1.0 - half) / self.alpha_x * drive
            x = x * full + (1.0 - full) / self.alpha_x * drive
            psi = torch.exp(-widths * (middle - centers) ** 2)
            remaining = 1.0 + torch.log(middle.clamp_min(1e-300)) / self.alpha_x
            ramp = (remaining * self.n_basis).clamp(0.0, 1.0)
            f = s * ramp**2 * (3.0 - 2.0 * ramp) * (psi @ weights) / (psi.sum(dim=1, keepdim=True) + 1e-300)
            if coupling_force is not None:
                f = f + coupling_force(now, g + e, v)
            e, v = phi[0, 0] * e + phi[0, 1] * v + gamma[0] * f, phi[1, 0] * e + phi[1, 1] * v + gamma[1] * f
            inputs.append(f)
            states.append(torch.stack([e, v], dim=1))
        # Every sample by an exact partial step from the grid point before it.
        u = t[None, :] / taus[:, None]  # (B, T)
        j = np.minimum(np.floor(u * n).astype(np.int64), steps - 1)
        phi_k, gamma_k = (torch.as_tensor(a, **options) for a in _system.step_matrices(u - j / n, self.omega))
        rows = torch.as_tensor(np.broadcast_to(np.arange(len(y0))[:, None], j.shape).copy(), device=self.device)
        index = torch.as_tensor(j, device=self.device)
        before = torch.stack(states)[index, rows]  # (B, T, 2, D)
        held = torch.stack(inputs)[index, rows]  # (B, T, D)
        state = torch.einsum("btij,btjd->btid", phi_k, before) + gamma_k[..., None] * held[:, :, None, :]
        e, v = state[:, :, 0], state[:, :, 1]
        taus_t = tau[:, :, None]
        acceleration = (-(self.omega**2) * e - 2.0 * self.omega * v + held) / taus_t**2
        return (g[:, None, :] + e).cpu().numpy(), (v / taus_t).cpu().numpy(), acceleration.cpu().numpy()

    # -- files ----------------------------------------------------------------------------------
    def to_arrays(self) -> dict[str, np.ndarray]:
        """The model as named arrays (JSON metadata and the weights (n_basis, n_dims)), no pickle."""
        meta = {
            "format": FORMAT,
            "version": VERSION,
            "n_dims": self.n_dims,
            "n_basis": self.n_basis,
            "alpha_z": self.alpha_z,
            "alpha_x": self.alpha_x,
            "regularization": self.regularization,
            "amplitude": self.amplitude,
            "extent": self.extent,
            "tau": self.tau,
            "dt": self.dt,
            "fit_rmse": self.fit_rmse,
            "n_demos": self.n_demos,
        }
        return {"meta": np.array(json.dumps(meta)), "weights": self.weights}

    @classmethod
    def from_arrays(cls, arrays: Any, source: str = "DMP data") -> DMP:
        """Rebuild a model written by :meth:`to_arrays`; anything else is an :class:`InputError`."""
        try:
            meta = json.loads(str(arrays["meta"]))
            if not isinstance(meta, dict) or meta.get("format") != FORMAT:
                raise ValueError(
                    f"format is {meta.get('format') if isinstance(meta, dict) else meta!r}, not {FORMAT!r}"
                )
            if meta.get("version") != VERSION:
                raise ValueError(f"version {meta.get('version')} is not supported (this is {VERSION})")
            numbers = ("alpha_z", "alpha_x", "regularization", "amplitude", "extent", "tau", "dt")
            bad = [name for name in numbers if not np.isfinite(float(meta[name]))]
            weights = np.asarray(arrays["weights"], dtype=np.float64)
            if bad:
                raise ValueError(f"{', '.join(bad)} not finite")
            dmp = cls(meta["n_dims"], meta["n_basis"], meta["alpha_z"], meta["alpha_x"], meta["regularization"])
            if weights.shape != (dmp.n_basis, dmp.n_dims):
                raise ValueError(
                    f"weights of shape {weights.shape} do not fit n_basis = {dmp.n_basis} and n_dims = {dmp.n_dims}"
                )
            if not np.all(np.isfinite(weights)):
                raise ValueError(f"{int(np.sum(~np.isfinite(weights)))} weights are not finite (NaN or inf)")
            if meta["tau"] <= 0 or meta["dt"] <= 0 or meta["amplitude"] ** 2 + meta["extent"] ** 2 <= 0:
                raise ValueError("tau, dt and the demonstrations' size must be positive")
            dmp.weights = weights
            dmp.amplitude, dmp.extent = float(meta["amplitude"]), float(meta["extent"])
            dmp.tau, dmp.dt = float(meta["tau"]), float(meta["dt"])
            dmp.fit_rmse, dmp.n_demos = float(meta["fit_rmse"]), int(meta["n_demos"])
            return dmp
        except (KeyError, ValueError, TypeError, json.JSONDecodeError, InputError) as error:
            raise InputError(f"{source} is not a vslsp DMP ({error}); re-create it with `vslsp teach`") from error

    def save(self, path: str | Path) -> None:
        """Write an ``.npz`` file (no pickle)."""
        arrays = self.to_arrays()
        with atomic_file(path) as stream:
            np.savez(stream, meta=arrays["meta"], weights=arrays["weights"])

    @classmethod
    def load(cls, path: str | Path) -> DMP:
        """Read a file written by :meth:`save`; a corrupt or foreign file is an :class:`InputError`."""
        if not os.path.lexists(path):
            raise InputError(f"there is no DMP file {shown(path)}; learn one with `vslsp teach`")
        try:
            arrays = load_npz(path, "DMP", MAX_FILE_BYTES)
        except InputError as error:
            raise InputError(f"cannot read DMP file {shown(path)}: {error}") from None
        return cls.from_arrays(arrays, source=shown(path))
