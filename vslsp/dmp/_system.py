"""The transformation system in normalised time, integrated exactly (closed form).

With normalised time u = t / τ, the offset from the goal e = y − g and its rate v = de/du = τ ẏ
(the DMP's z), the transformation system of Ijspeert et al. (2013, eq. 2.1) with β_z = α_z / 4
is a critically damped spring driven by the forcing term f, and no longer depends on τ:

    e'' = −ω² e − 2ω e' + f(u),        ω = α_z / 2.

The forcing term is held over steps of 1/N in u (zero-order hold). For a held input the state
(e, v) after a step δ is exactly ``Φ(δ) (e, v) + Γ(δ) f`` with

    Φ(δ) = exp(−ωδ) [[1 + ωδ, δ], [−ω²δ, 1 − ωδ]],
    Γ(δ) = [(1 − exp(−ωδ)(1 + ωδ)) / ω², δ exp(−ωδ)],

so a rollout has no integration error: the model *is* this discrete-input system, the fit
uses the same responses as the rollout, and any sample time (any τ, any dt) is evaluated
exactly by a partial step from the last grid point. After u = 1 the forcing term is zero and
the state is the free spring's, ``Φ(u − 1)`` applied to the state at u = 1.
"""

from __future__ import annotations

import numpy as np

STEPS = 1000  # N: forcing-term holds per τ


def step_matrices(delta: np.ndarray, omega: float) -> tuple[np.ndarray, np.ndarray]:
    """Transition and input matrices of a step of length ``delta`` in u.

    Parameters
    ----------
    delta : array, shape (...)
        Step lengths in normalised time (>= 0).
    omega : float
        Natural frequency in normalised time, α_z / 2.

    Returns
    -------
    phi : array, shape (..., 2, 2)
        State transition.
    gamma : array, shape (..., 2)
        Response of (e, v) to a unit input held over the step, from rest.
    """
    delta = np.asarray(delta, dtype=np.float64)
    decay = np.exp(-omega * delta)
    phi = np.empty((*delta.shape, 2, 2))
    phi[..., 0, 0] = decay * (1.0 + omega * delta)
    phi[..., 0, 1] = decay * delta
    phi[..., 1, 0] = -decay * omega**2 * delta
    phi[..., 1, 1] = decay * (1.0 - omega * delta)
    gamma = np.empty((*delta.shape, 2))
    gamma[..., 0] = (1.0 - decay * (1.0 + omega * delta)) / omega**2
    gamma[..., 1] = decay * delta
    return phi, gamma


def free_response(u: np.ndarray, omega: float) -> np.ndarray:
    """(e, v) of the unforced spring released at rest from e = 1, at times ``u`` (...) -> (..., 2)."""
    u = np.asarray(u, dtype=np.float64)
    decay = np.exp(-omega * u)
    return np.stack([decay * (1.0 + omega * u), -decay * omega**2 * u], axis=-1)


def grid_responses(inputs: np.ndarray, omega: float) -> np.ndarray:
    """States at the grid points u_j = j / N driven by held ``inputs``, from rest.

    Parameters
    ----------
    inputs : array, shape (N, C)
        The input of each channel held over [u_j, u_j+1).
    omega : float
        Natural frequency in normalised time.

    Returns
    -------
    states : array, shape (N + 1, 2, C)
        (e, v) of every channel at u_0 = 0 ... u_N = 1.
    """
    n = inputs.shape[0]
    phi, gamma = step_matrices(np.array(1.0 / n), omega)
    states = np.zeros((n + 1, 2, inputs.shape[1]))
    for j in range(n):
        states[j + 1] = phi @ states[j] + gamma[:, None] * inputs[j]
    return states


def at_phases(states: np.ndarray, inputs: np.ndarray, u: np.ndarray, omega: float) -> np.ndarray:
    """Channel states at arbitrary normalised times, by an exact partial step from the grid.

    Parameters
    ----------
    states : array, shape (N + 1, 2, C)
        Grid states from :func:`grid_responses`.
    inputs : array, shape (N, C)
        The held inputs they were driven by.
    u : array, shape (...)
        Normalised times (>= 0); past 1 the inputs are zero and the spring runs free.
    omega : float
        Natural frequency in normalised time.

    Returns
    -------
    array, shape (..., 2, C)
        (e, v) of every channel at ``u``.
    """
    n = inputs.shape[0]
    u = np.asarray(u, dtype=np.float64)
    j = np.clip(np.floor(u * n).astype(np.int64), 0, n)
    inside = j < n
    delta = np.where(inside, u - j / n, u - 1.0)
    phi, gamma = step_matrices(delta, omega)
    held = np.where(inside[..., None], inputs[np.minimum(j, n - 1)], 0.0)  # (..., C)
    return np.einsum("...ab,...bc->...ac", phi, states[j]) + gamma[..., :, None] * held[..., None, :]


def held_input(inputs: np.ndarray, u: np.ndarray) -> np.ndarray:
    """The input in force at normalised times ``u`` (...): (..., C), zero from u = 1 on."""
    n = inputs.shape[0]
    j = np.floor(np.asarray(u, dtype=np.float64) * n).astype(np.int64)
    inside = (j >= 0) & (j < n)
    return np.where(inside[..., None], inputs[np.clip(j, 0, n - 1)], 0.0)
