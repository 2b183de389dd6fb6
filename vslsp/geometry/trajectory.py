"""The pick-and-place trajectory of the original VSL (paper, "Methodology", Algorithm 1 part II
``executeAction``, equations traj1-traj3 and the rotation profile of Figure "trajROT").

A pick-and-place operation is a cycle rest → pick → place → rest. Each of the three segments
is a geometric path in a path parameter s ∈ [0, 1]:

    p_x(s) = a_3 s³ + a_2 s² + a_1 s + a_0                    (traj1)
    p_y(s) = b_3 s³ + b_2 s² + b_1 s + b_0                    (traj2)
    p_z(s) = h [1 − |(tanh⁻¹(h_0 (s − 0.5)))^κ|]              (traj3)

with the cubic coefficients fixed by the positions and path velocities at both ends. As
printed, (traj3) is zero at the ends only for h_0 = 2 tanh(1) and is undefined for a negative
base and a non-integer κ; we use the normalised, sign-free form

    bump(s) = h [1 − |tanh⁻¹(h_0 (s − 0.5)) / tanh⁻¹(h_0 / 2)|^κ]

which equals the paper's for h_0 = 2 tanh(1), is zero at s = 0 and s = 1 and h at s = 0.5 for
every 0 < h_0 < 2 (where tanh⁻¹ is defined) and κ > 0: h_0 shapes how steeply the hand rises
and lands, κ how flat the top is. Ends at different heights (objects on different levels) add
a cubic blend z_0 + (z_1 − z_0)(3s² − 2s³). Time is spread with a third-order polynomial
s(t) = 3τ² − 2τ³, τ = (t − t_start)/(t_final − t_start), so every segment starts and ends at
rest. The hand's rotation follows a trapezoidal velocity profile from θ_pick to θ_place
(from 0 at rest to θ_pick on the way to the object, back to 0 on the way home).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vslsp.errors import InputError

PAPER_H0 = 2.0 * float(np.tanh(1.0))  # the h_0 for which the printed (traj3) is zero at the ends


@dataclass(frozen=True)
class TrajectoryParameters:
    """Shape of a pick-and-place cycle: ``height`` h (the bump's height at mid-path, in the
    units of the positions), ``h0`` h_0 ∈ (0, 2), ``kappa`` κ > 0, the ``durations`` (s) of
    the rest→pick, pick→place and place→rest segments, ``samples`` per segment, and the
    ``blend`` fraction of a segment the trapezoidal rotation spends accelerating (and as much
    decelerating), in (0, 0.5]."""

    height: float = 0.05
    h0: float = PAPER_H0
    kappa: float = 2.0
    durations: tuple[float, float, float] = (2.0, 3.0, 2.0)
    samples: int = 50
    blend: float = 0.25

    def __post_init__(self) -> None:
        check_height_parameters(self.height, self.h0, self.kappa)
        if len(self.durations) != 3 or any(not np.isfinite(d) or d <= 0.0 for d in self.durations):
            raise InputError(
                f"durations must be three positive seconds (rest->pick, pick->place, "
                f"place->rest), got {self.durations!r}"
            )
        if int(self.samples) != self.samples or self.samples < 2:
            raise InputError(f"samples per segment must be an integer >= 2, got {self.samples!r}")
        check_blend(self.blend)

    def to_dict(self) -> dict:
        return {
            "height": self.height,
            "h0": self.h0,
            "kappa": self.kappa,
            "durations": list(self.durations),
            "samples": self.samples,
            "blend": self.blend,
        }


@dataclass(frozen=True, eq=False)
class PickPlaceTrajectory:
    """A whole rest → pick → place → rest cycle: times ``t`` (T,) s, hand positions ``xyz``
    (T, 3), hand rotation ``theta`` (T,) rad, and the ``segments`` (3,) index where each
    segment starts in those arrays (rest→pick, pick→place, place→rest; the key points are
    shared between consecutive segments, so they appear once)."""

    t: np.ndarray
    xyz: np.ndarray
    theta: np.ndarray
    segments: tuple[int, int, int]
    parameters: TrajectoryParameters

    @property
    def key_points(self) -> np.ndarray:
        """Rest, pick, place (3, 3) as the hand passes them."""
        return self.xyz[[0, self.segments[1], self.segments[2]]]

    def to_dict(self) -> dict:
        return {
            "t": self.t.round(6).tolist(),
            "xyz": self.xyz.round(6).tolist(),
            "theta": self.theta.round(6).tolist(),
            "segments": list(self.segments),
            "parameters": self.parameters.to_dict(),
        }


def check_height_parameters(height: float, h0: float, kappa: float) -> None:
    """Raise InputError unless h ≥ 0, 0 < h_0 < 2 (tanh⁻¹(h_0/2) defined and non-zero) and κ > 0."""
    if not np.isfinite(height) or height < 0.0:
        raise InputError(f"the height h of the path must be >= 0, got {height!r}")
    if not np.isfinite(h0) or not 0.0 < h0 < 2.0:
        raise InputError(
            f"h0 must lie in (0, 2) so that atanh(h0 (s - 0.5)) is defined on s in [0, 1], "
            f"got {h0!r} (the paper's profile uses h0 = 2 tanh(1) = {PAPER_H0:.4f})"
        )
    if not np.isfinite(kappa) or kappa <= 0.0:
        raise InputError(f"the curvature kappa must be > 0, got {kappa!r}")


def check_blend(blend: float) -> None:
    if not np.isfinite(blend) or not 0.0 < blend <= 0.5:
        raise InputError(f"the rotation profile's blend must lie in (0, 0.5], got {blend!r}")


def cubic_path(
    start: np.ndarray,
    end: np.ndarray,
    s: np.ndarray,
    start_velocity: np.ndarray | None = None,
    end_velocity: np.ndarray | None = None,
) -> np.ndarray:
    """(traj1, traj2): points (N, D) of the cubic from ``start`` (D,) to ``end`` (D,) at path
    parameters ``s`` (N,), with path velocities dp/ds at the ends (default zero)."""
    p0, p1 = np.asarray(start, float), np.asarray(end, float)
    v0 = np.zeros_like(p0) if start_velocity is None else np.asarray(start_velocity, float)
    v1 = np.zeros_like(p0) if end_velocity is None else np.asarray(end_velocity, float)
    a0, a1 = p0, v0
    a2 = 3.0 * (p1 - p0) - 2.0 * v0 - v1
    a3 = -2.0 * (p1 - p0) + v0 + v1
    s = np.asarray(s, float)[:, None]
    return a0 + a1 * s + a2 * s**2 + a3 * s**3


def height_profile(s: np.ndarray, height: float, h0: float = PAPER_H0, kappa: float = 2.0) -> np.ndarray:
    """(traj3), normalised: h [1 − |tanh⁻¹(h_0 (s − 0.5)) / tanh⁻¹(h_0/2)|^κ] at ``s`` (N,) in [0, 1]."""
    check_height_parameters(height, h0, kappa)
    s = np.asarray(s, float)
    if np.any((s < 0.0) | (s > 1.0)):
        raise InputError("the path parameter s must lie in [0, 1]")
    ratio = np.arctanh(h0 * (s - 0.5)) / np.arctanh(h0 / 2.0)
    return height * (1.0 - np.abs(ratio) ** kappa)


def time_scaling(t: np.ndarray, t_start: float, t_final: float) -> np.ndarray:
    """s(t) = 3τ² − 2τ³ with τ = (t − t_start)/(t_final − t_start) clipped to [0, 1], for ``t`` (N,)."""
    if not (np.isfinite(t_start) and np.isfinite(t_final)) or t_final <= t_start:
        raise InputError(f"t_final must be later than t_start, got t_start={t_start!r}, t_final={t_final!r}")
    tau = np.clip((np.asarray(t, float) - t_start) / (t_final - t_start), 0.0, 1.0)
    return tau * tau * (3.0 - 2.0 * tau)


def trapezoidal_profile(tau: np.ndarray, start: float, end: float, blend: float = 0.25) -> np.ndarray:
    """Angle (N,) from ``start`` to ``end`` at normalised times ``tau`` (N,) in [0, 1]: constant
    acceleration for the first ``blend`` of the time, constant speed, constant deceleration for
    the last ``blend`` (a trapezoidal velocity profile)."""
    check_blend(blend)
    tau = np.clip(np.asarray(tau, float), 0.0, 1.0)
    peak = 1.0 / (1.0 - blend)  # speed (per unit tau) on the flat part, so the area is 1
    rising = 0.5 * peak / blend * tau**2
    flat = peak * (tau - 0.5 * blend)
    falling = 1.0 - 0.5 * peak / blend * (1.0 - tau) ** 2
    fraction = np.where(tau < blend, rising, np.where(tau <= 1.0 - blend, flat, falling))
    return start + (end - start) * fraction


def segment(
    start: np.ndarray,
    end: np.ndarray,
    theta_start: float,
    theta_end: float,
    t_start: float,
    t_final: float,
    parameters: TrajectoryParameters,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One segment between key points ``start`` and ``end`` (3,) (x, y, z): times (N,),
    positions (N, 3) and rotation (N,), with N = ``parameters.samples``."""
    t = np.linspace(t_start, t_final, parameters.samples)
    s = time_scaling(t, t_start, t_final)
    start, end = np.asarray(start, float), np.asarray(end, float)
    xy = cubic_path(start[:2], end[:2], s)
    z = cubic_path(start[2:], end[2:], s)[:, 0] + height_profile(s, parameters.height, parameters.h0, parameters.kappa)
    theta = trapezoidal_profile((t - t_start) / (t_final - t_start), theta_start, theta_end, parameters.blend)
    return t, np.column_stack([xy, z]), theta


def pick_and_place(
    rest: np.ndarray,
    pick: np.ndarray,
    place: np.ndarray,
    theta_pick: float,
    theta_place: float,
    parameters: TrajectoryParameters | None = None,
    t_start: float = 0.0,
    theta_rest: float = 0.0,
) -> PickPlaceTrajectory:
    """The cycle rest → pick → place → rest through key points (3,) each (x, y, z), the hand
    turning from ``theta_rest`` to ``theta_pick`` (rad) on the way to the object, to
    ``theta_place`` while carrying it, and back to ``theta_rest``."""
    parameters = parameters or TrajectoryParameters()
    points = [np.asarray(p, float).reshape(-1) for p in (rest, pick, place)]
    if any(p.shape != (3,) or not np.all(np.isfinite(p)) for p in points):
        raise InputError("rest, pick and place must each be three finite numbers (x, y, z)")
    if not np.all(np.isfinite([theta_pick, theta_place, theta_rest, t_start])):
        raise InputError("the rotation angles and t_start must be finite")
    rest, pick, place = points
    legs = (
        (rest, pick, theta_rest, theta_pick),
        (pick, place, theta_pick, theta_place),
        (place, rest, theta_place, theta_rest),
    )
    times: list[np.ndarray] = []
    positions: list[np.ndarray] = []
    angles: list[np.ndarray] = []
    starts: list[int] = []
    clock = t_start
    for k, ((a, b, theta_a, theta_b), duration) in enumerate(zip(legs, parameters.durations)):
        t, xyz, theta = segment(a, b, theta_a, theta_b, clock, clock + duration, parameters)
        skip = 0 if k == 0 else 1  # the key point ends the previous segment already
        starts.append(sum(len(x) for x in times) - skip)
        times.append(t[skip:])
        positions.append(xyz[skip:])
        angles.append(theta[skip:])
        clock += duration
    return PickPlaceTrajectory(
        np.concatenate(times), np.concatenate(positions), np.concatenate(angles), (0, starts[1], starts[2]), parameters
    )
