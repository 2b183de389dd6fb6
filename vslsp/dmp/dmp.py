"""Discrete DMP: transformation system, canonical system, Gaussian-basis forcing term, LWR.

Ijspeert, Nakanishi, Hoffmann, Pastor, Schaal (2013), "Dynamical movement primitives:
learning attractor models for motor behaviors", Neural Computation 25(2):

    τ ż = α_z (β_z (g − y) − z) + f(x) + C_f,     τ ẏ = z,       β_z = α_z / 4
    τ ẋ = −α_x x + C_c
    f(x) = Σ_i ψ_i(x) w_i / Σ_i ψ_i(x) · x · s,    ψ_i(x) = exp(−h_i (x − c_i)²)

The paper's amplitude factor is ``s = g − y0`` per dimension. That factor mirrors the
movement when a new goal lies on the other side of the start and blows it up when the
demonstrated amplitude was near zero. We use one scalar per rollout instead,
``s = ‖g − y0‖ / A``, with ``A`` the mean demonstrated amplitude: the shape of the forcing
term keeps its direction (no mirroring), it shrinks to nothing as the goal approaches the
start (no blow-up; the spring alone then holds the goal), and it scales with the size of the
movement like the original. With a single dimension this is ``|g − y0| / |g_d − y0_d|``.

Weights are fitted per basis function and dimension in closed form by locally weighted
regression over all samples of all demonstrations, each with its own start, goal and duration.

Rollouts integrate with semi-implicit Euler steps of at most τ/1000. Without coupling terms
the phase is the same for every movement and the transformation system is linear in
(y0 − g, s·f), so a batch shares one integration and each movement is a linear combination of
its responses; with couplings every movement is stepped.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np
import torch

from vslsp.errors import InputError

FORMAT = "vslsp-dmp"
VERSION = 1
Coupling = Callable[[torch.Tensor, torch.Tensor, torch.Tensor], torch.Tensor]


@dataclass(frozen=True)
class Rollout:
    """A reproduced movement: t (T,), and y, yd, ydd of shape (T, D), or (B, T, D) when batched."""

    t: np.ndarray
    y: np.ndarray
    yd: np.ndarray
    ydd: np.ndarray


def _default_device() -> torch.device:
    return torch.device("cuda") if torch.cuda.is_available() else torch.device("cpu")


class DMP:
    """A discrete DMP over ``n_dims`` dimensions with ``n_basis`` Gaussian basis functions."""

    def __init__(self, n_dims: int, n_basis: int = 50, alpha_z: float = 25.0, alpha_x: float = 4.6,
                 device: str | torch.device | None = None) -> None:
        if n_dims < 1 or n_basis < 2:
            raise InputError(f"a DMP needs n_dims >= 1 and n_basis >= 2, got {n_dims}, {n_basis}")
        self.n_dims, self.n_basis = n_dims, n_basis
        self.alpha_z, self.beta_z, self.alpha_x = float(alpha_z), float(alpha_z) / 4.0, float(alpha_x)
        self.device = torch.device(device) if device is not None else _default_device()
        # Centres evenly spaced in time, so in phase x = exp(−α_x t/τ); widths from neighbours.
        self.centers = np.exp(-self.alpha_x * np.linspace(0.0, 1.0, n_basis))
        spacing = np.diff(self.centers)
        # h_i = 3 / Δc²: narrow enough that locally weighted regression, which fits every
        # basis function alone, is not blurred by its neighbours.
        self.widths = 3.0 / np.concatenate([spacing, spacing[-1:]]) ** 2
        self.weights = np.zeros((n_basis, n_dims))
        self.amplitude = 1.0  # A: mean demonstrated ‖g − y0‖
        self.tau = 1.0  # mean demonstrated duration (s)
        self.dt = 0.01  # sample period of the demonstrations (s)
        self.fit_rmse = float("nan")
        self.n_demos = 0

    # -- the model ------------------------------------------------------------------------
    def _basis(self, x: np.ndarray) -> np.ndarray:
        """ψ (N, n_basis) at phases x (N,)."""
        return np.exp(-self.widths * (x[:, None] - self.centers) ** 2)

    def _scale(self, y0: np.ndarray, goal: np.ndarray) -> np.ndarray:
        """The amplitude factor s (..., 1) of each movement."""
        norm = np.linalg.norm(goal - y0, axis=-1, keepdims=True)
        return norm / self.amplitude if self.amplitude > 1e-6 else np.ones_like(norm)

    # -- learning ---------------------------------------------------------------------------
    def fit(self, demos: list[tuple[np.ndarray, np.ndarray]]) -> DMP:
        """Learn the weights from demonstrations ``[(t (T,), y (T, D)), ...]``."""
        if not demos:
            raise InputError("fit needs at least one demonstration")
        checked = []
        for k, (t, y) in enumerate(demos):
            t, y = np.asarray(t, dtype=np.float64), np.asarray(y, dtype=np.float64)
            if y.ndim != 2 or y.shape[1] != self.n_dims or t.shape != (len(y),) or len(t) < 5:
                raise InputError(
                    f"demonstration {k}: expected t (T,) and y (T, {self.n_dims}) with T >= 5, "
                    f"got {t.shape} and {y.shape}"
                )
            checked.append((t - t[0], y))
        self.amplitude = float(np.mean([np.linalg.norm(y[-1] - y[0]) for _, y in checked]))
        self.tau = float(np.mean([t[-1] for t, _ in checked]))
        self.dt = float(np.mean([np.mean(np.diff(t)) for t, _ in checked]))
        phases, features, targets = [], [], []
        for t, y in checked:
            tau = t[-1]
            yd = np.gradient(y, t, axis=0)
            ydd = np.gradient(yd, t, axis=0)
            y0, goal = y[0], y[-1]
            x = np.exp(-self.alpha_x * t / tau)
            target = tau**2 * ydd - self.alpha_z * (self.beta_z * (goal - y) - tau * yd)
            phases.append(x)
            features.append(x * self._scale(y0, goal)[0])
            targets.append(target)
        x, xi, target = np.concatenate(phases), np.concatenate(features), np.concatenate(targets)
        psi = self._basis(x)  # (N, n_basis)
        numerator = psi.T @ (xi[:, None] * target)  # (n_basis, D)
        denominator = psi.T @ (xi**2) + 1e-10  # (n_basis,)
        self.weights = numerator / denominator[:, None]
        self.n_demos = len(checked)
        errors = [
            self.rollout(y[0], y[-1], tau=t[-1], dt=float(np.mean(np.diff(t))), duration=t[-1]).y[: len(y)] - y
            for t, y in checked
        ]
        self.fit_rmse = float(np.sqrt(np.mean(np.concatenate([np.sum(e**2, axis=1) for e in errors]))))
        return self

    # -- reproduction -------------------------------------------------------------------------
    def rollout(self, y0: np.ndarray, goal: np.ndarray, tau: float | None = None, dt: float | None = None,
                duration: float | None = None, coupling_force: Coupling | None = None,
                coupling_phase: Coupling | None = None) -> Rollout:
        """Integrate from ``y0`` to ``goal`` ((D,) or batched (B, D)).

        ``tau`` is the movement's duration (default: the demonstrations'); the rollout runs for
        ``duration`` (default 1.3 τ, time for the spring to settle on the goal). Coupling terms
        are callables ``(t, y, z) -> (B, D)`` tensors for C_f and ``(t, x, _) -> (B, 1)`` for C_c.
        """
        y0 = np.asarray(y0, dtype=np.float64)
        goal = np.asarray(goal, dtype=np.float64)
        batched = y0.ndim == 2 or goal.ndim == 2
        y0, goal = np.broadcast_arrays(np.atleast_2d(y0), np.atleast_2d(goal))
        if y0.shape[1] != self.n_dims:
            raise InputError(f"start and goal must have {self.n_dims} dimensions, got {y0.shape[1]}")
        tau = self.tau if tau is None else float(tau)
        dt = self.dt if dt is None else float(dt)
        if tau <= 0 or dt <= 0:
            raise InputError(f"tau and dt must be positive, got {tau}, {dt}")
        duration = 1.3 * tau if duration is None else float(duration)
        steps = int(round(duration / dt)) + 1
        if steps < 2:
            raise InputError(f"a rollout of {duration} s is shorter than one sample period dt = {dt} s")
        # Semi-implicit Euler needs steps well below the spring's time constant: integrate
        # with at least 1000 substeps per τ and report every ``dt``.
        substeps = max(1, int(np.ceil(dt / (tau / 1000.0))))
        h = dt / substeps
        options = {"dtype": torch.float64, "device": self.device}
        y0_t, g = torch.as_tensor(y0, **options), torch.as_tensor(goal, **options)
        scale = torch.as_tensor(self._scale(y0, goal), **options)  # (B, 1)
        if coupling_force is None and coupling_phase is None:
            y, yd, ydd = self._superpose(y0_t, g, scale, tau, h, substeps, steps)
        else:
            y, zd = self._integrate(y0_t, g, scale, tau, h, substeps, steps, coupling_force, coupling_phase)
            y, ydd = y.cpu().numpy(), zd.cpu().numpy() / tau
            yd = np.gradient(y, dt, axis=1)
        t = np.arange(steps) * dt
        if not batched:
            return Rollout(t=t, y=y[0], yd=yd[0], ydd=ydd[0])
        return Rollout(t=t, y=y, yd=yd, ydd=ydd)

    def _integrate(self, y0: torch.Tensor, g: torch.Tensor, scale: torch.Tensor, tau: float, h: float,
                   substeps: int, steps: int, coupling_force: Coupling | None,
                   coupling_phase: Coupling | None) -> tuple[torch.Tensor, torch.Tensor]:
        """y and ż (B, T, D) every ``substeps`` steps of semi-implicit Euler with couplings."""
        options = {"dtype": torch.float64, "device": self.device}
        y = y0.clone()
        z = torch.zeros_like(y)
        x = torch.ones((y.shape[0], 1), **options)
        weights = torch.as_tensor(self.weights, **options)
        centers = torch.as_tensor(self.centers, **options)
        widths = torch.as_tensor(self.widths, **options)
        ys, zds = [], []
        for step in range((steps - 1) * substeps + 1):
            t = torch.tensor(step * h, **options)
            psi = torch.exp(-widths * (x - centers) ** 2)  # (B, n_basis)
            forcing = (psi @ weights) / (psi.sum(dim=1, keepdim=True) + 1e-10) * x * scale
            if coupling_force is not None:
                forcing = forcing + coupling_force(t, y, z)
            zd = (self.alpha_z * (self.beta_z * (g - y) - z) + forcing) / tau
            if step % substeps == 0:
                ys.append(y)
                zds.append(zd)
            xd = -self.alpha_x * x
            if coupling_phase is not None:
                xd = xd + coupling_phase(t, x, x)
            z = z + zd * h
            y = y + z / tau * h
            x = x + xd / tau * h
        return torch.stack(ys, dim=1), torch.stack(zds, dim=1)

    def _responses(self, tau: float, h: float, substeps: int, steps: int) -> tuple[np.ndarray, ...]:
        """The rollout's building blocks at the T reported steps, from the same Euler steps.

        Without couplings the phase is the same for every movement and the transformation
        system is linear in (y0 − g, s·f), so each rollout is
        ``y = g + P (y0 − g) + s F`` and ``z = Q (y0 − g) + s G``. Returns P, Q (T,), F, G and
        the unscaled forcing term φ (T, D).
        """
        n = (steps - 1) * substeps + 1
        x = (1.0 - self.alpha_x * h / tau) ** np.arange(n)  # canonical system, Euler steps
        psi = self._basis(x)
        forcing = (psi @ self.weights) / (psi.sum(axis=1, keepdims=True) + 1e-10) * x[:, None]  # (n, D)
        # One Euler step of (e = y − g, z) with input u = s·f is (e, z) ← A (e, z) + b u; a
        # reported step is ``substeps`` of them: A^m and the kernel A^(m−1−j) b weigh the
        # inputs inside it, so the time loop runs over reported steps only.
        rate, stiffness, damping = h / tau, self.alpha_z * self.beta_z / tau, self.alpha_z / tau
        euler = np.array([[1.0 - rate * h * stiffness, rate * (1.0 - h * damping)],
                         [-h * stiffness, 1.0 - h * damping]])
        kernel = [np.array([rate * rate, rate])]  # A^j b, j = 0..m−1
        for _ in range(substeps - 1):
            kernel.append(euler @ kernel[-1])
        kernel = np.stack(kernel[::-1])  # (m, 2): A^(m−1−j) b
        interval = np.linalg.matrix_power(euler, substeps)
        drive = np.einsum("js,kjd->ksd", kernel, forcing[:-1].reshape(steps - 1, substeps, self.n_dims))
        # Channel 0: the free spring from e = 1; channels 1..D: unit-amplitude forcing, from rest.
        state = np.zeros((2, self.n_dims + 1))
        state[0, 0] = 1.0
        states = np.empty((steps, 2, self.n_dims + 1))
        states[0] = state
        for k in range(steps - 1):
            state = interval @ state
            state[:, 1:] += drive[k]
            states[k + 1] = state
        es, zs = states[:, 0], states[:, 1]
        return es[:, 0], zs[:, 0], es[:, 1:], zs[:, 1:], forcing[::substeps]

    def _superpose(self, y0: torch.Tensor, g: torch.Tensor, scale: torch.Tensor, tau: float, h: float,
                   substeps: int, steps: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """y, ẏ, ÿ (B, T, D) of uncoupled rollouts: one integration shared by the whole batch.

        Each is a fixed linear map of (g, y0 − g, s), one matrix product for the batch: y from
        P and F; ẏ, the samples' central differences, from those of P and F; ÿ = ż / τ from
        ``−α_z β_z (y − g) − α_z z + s φ``.
        """
        p, q, f, gf, forcing = self._responses(tau, h, substeps, steps)
        dt, d = h * substeps, self.n_dims
        blocks = {  # output: (coefficient of g, of y0 − g per step (T,), of s per step (T, D))
            "y": (1.0, p, f),
            "yd": (0.0, np.gradient(p, dt), np.gradient(f, dt, axis=0)),
            "ydd": (0.0, -(self.alpha_z * self.beta_z * p + self.alpha_z * q) / tau**2,
                    (forcing - self.alpha_z * self.beta_z * f - self.alpha_z * gf) / tau**2),
        }
        options = {"dtype": torch.float64, "device": self.device}
        inputs = torch.cat([g, y0 - g, scale], dim=1)  # (B, 2D + 1)
        outputs = []
        for of_goal, of_offset, of_scale in blocks.values():
            linear = np.zeros((2 * d + 1, steps, d))
            for k in range(d):
                linear[k, :, k] = of_goal
                linear[d + k, :, k] = of_offset
            linear[2 * d] = of_scale
            product = inputs @ torch.as_tensor(linear.reshape(2 * d + 1, steps * d), **options)
            outputs.append(product.reshape(-1, steps, d).cpu().numpy())
        return tuple(outputs)

    # -- files ----------------------------------------------------------------------------------
    def to_arrays(self) -> dict[str, np.ndarray]:
        meta = {
            "format": FORMAT, "version": VERSION, "n_dims": self.n_dims, "n_basis": self.n_basis,
            "alpha_z": self.alpha_z, "alpha_x": self.alpha_x, "amplitude": self.amplitude,
            "tau": self.tau, "dt": self.dt, "fit_rmse": self.fit_rmse, "n_demos": self.n_demos,
        }
        return {"meta": np.array(json.dumps(meta)), "weights": self.weights}

    @classmethod
    def from_arrays(cls, arrays, source: str = "DMP data") -> DMP:
        try:
            meta = json.loads(str(arrays["meta"]))
            if meta.get("format") != FORMAT:
                raise ValueError(f"format is {meta.get('format')!r}, not {FORMAT!r}")
            if meta.get("version") != VERSION:
                raise ValueError(f"version {meta.get('version')} is not supported (this is {VERSION})")
            dmp = cls(meta["n_dims"], meta["n_basis"], meta["alpha_z"], meta["alpha_x"])
            weights = np.asarray(arrays["weights"], dtype=np.float64)
            if weights.shape != (dmp.n_basis, dmp.n_dims) or not np.all(np.isfinite(weights)):
                raise ValueError(f"weights of shape {weights.shape} do not fit the parameters")
            dmp.weights = weights
            dmp.amplitude, dmp.tau, dmp.dt = meta["amplitude"], meta["tau"], meta["dt"]
            dmp.fit_rmse, dmp.n_demos = meta["fit_rmse"], meta["n_demos"]
            return dmp
        except (KeyError, ValueError, TypeError, json.JSONDecodeError) as error:
            raise InputError(f"{source} is not a vslsp DMP ({error}); re-create it with `vslsp teach`") from error

    def save(self, path: str | Path) -> None:
        """Write an ``.npz`` file (no pickle)."""
        np.savez(Path(path), **self.to_arrays())

    @classmethod
    def load(cls, path: str | Path) -> DMP:
        """Read a file written by :meth:`save`; a corrupt or foreign file is an :class:`InputError`."""
        try:
            with np.load(Path(path), allow_pickle=False) as data:
                arrays = {key: data[key] for key in data.files}
        except FileNotFoundError as error:
            raise InputError(f"there is no DMP file {path}; learn one with `vslsp teach`") from error
        except (OSError, ValueError, EOFError) as error:
            raise InputError(f"cannot read DMP file {path}: {error}") from error
        except Exception as error:  # zipfile.BadZipFile and friends
            raise InputError(f"cannot read DMP file {path}: it is corrupt ({error})") from error
        return cls.from_arrays(arrays, source=f"{path}")
