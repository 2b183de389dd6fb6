"""Canonical system, gated forcing term and the scale-free amplitude factor.

The canonical system is Ijspeert et al.'s (2013, eq. 2.2), τ ẋ = −α_x x (+ C_c), so that
x = exp(−α_x t / τ) and x(τ) = exp(−α_x). The forcing term's Gaussian basis functions are
spaced evenly in time (centres x_i = exp(−α_x i / n)); their normalised sum is multiplied by a
gate γ(x) that is 1 until the last basis interval and falls to 0 with zero slope at x(τ)
(a smoothstep in normalised time), instead of the paper's gate x, which is still 0.01 at τ:

    f(x) = s · γ(x) · Σ_i ψ_i(x) w_i / Σ_i ψ_i(x),      ψ_i(x) = exp(−h_i (x − c_i)²).

The amplitude factor s of a movement from y0 to g (see :func:`amplitude_factor`) blends the
distance scaling of Ijspeert et al. (‖g − y0‖ / A) with no scaling (Pastor et al. 2009),
weighted by how much of the demonstration is transport (its start-goal distance A) and how
much is shape (its extent E off the start-goal line).
"""

from __future__ import annotations

import numpy as np

OVERLAP = 0.5  # a basis function's value at its neighbours' centres


def centres_and_widths(n_basis: int, alpha_x: float) -> tuple[np.ndarray, np.ndarray]:
    """Basis centres c (n_basis,) evenly spaced in time over [0, τ), and widths h (n_basis,)."""
    centres = np.exp(-alpha_x * np.arange(n_basis) / n_basis)
    spacing = np.abs(np.diff(np.append(centres, np.exp(-alpha_x))))
    return centres, np.log(1.0 / OVERLAP) / spacing**2


def gate(x: np.ndarray, n_basis: int, alpha_x: float) -> np.ndarray:
    """γ (...) at phases x (...): 1 until the last basis interval, then a smoothstep to 0 at x(τ)."""
    with np.errstate(divide="ignore"):
        remaining = 1.0 + np.log(np.maximum(np.asarray(x, dtype=np.float64), 0.0)) / alpha_x  # 1 − t/τ
    s = np.clip(remaining * n_basis, 0.0, 1.0)
    return s * s * (3.0 - 2.0 * s)


def basis(x: np.ndarray, centres: np.ndarray, widths: np.ndarray, alpha_x: float) -> np.ndarray:
    """The gated, normalised basis γ(x) ψ_i(x) / Σ_j ψ_j(x): (..., n_basis) at phases x (...)."""
    x = np.asarray(x, dtype=np.float64)
    psi = np.exp(-widths * (x[..., None] - centres) ** 2)
    return gate(x, len(centres), alpha_x)[..., None] * psi / (psi.sum(axis=-1, keepdims=True) + 1e-300)


def grid_phases(steps: int, alpha_x: float) -> np.ndarray:
    """Phase x (steps,) at the middle of each held interval [j, j + 1) / steps of normalised time."""
    return np.exp(-alpha_x * (np.arange(steps) + 0.5) / steps)


def chord_extent(y: np.ndarray) -> float:
    """E of one demonstration y (T, D): its largest distance from the segment start-goal."""
    start, chord = y[0], y[-1] - y[0]
    length2 = float(chord @ chord)
    along = np.clip((y - start) @ chord / length2, 0.0, 1.0) if length2 > 0 else np.zeros(len(y))
    return float(np.linalg.norm(y - start - along[:, None] * chord, axis=1).max())


def amplitude_factor(distance: np.ndarray, amplitude: float, extent: float) -> np.ndarray:
    """s = (D A + E²) / (A² + E²) for start-goal distances D (...).

    With w = A² / (A² + E²) this is ``w · D / A + (1 − w) · 1``: a movement that is all
    transport (E = 0) scales with its distance as in Ijspeert et al., a closed shape (A = 0)
    keeps its demonstrated size whatever the goal, and the demonstration itself (D = A) gets 1.
    The denominator is the demonstration's squared size, never 0 for a movement that moves,
    and s E <= E + D / 2, s A <= D + E / 2: no excursion grows faster than the distance.
    """
    return (np.asarray(distance) * amplitude + extent**2) / (amplitude**2 + extent**2)
