"""Decomposition of the estimated transform (paper, "Methodology", match finding):

    α T_sift = T R_θ R_−φ S_v R_φ P

P is the pure projective part (last row of α T_sift), T_A = α T_sift P⁻¹ the affine remainder,
T its translation (third column), and A (2×2, the rest of T_A) = U D Vᵀ by SVD, so that
S_v = diag(D), R_θ = U Vᵀ and R_φ = Vᵀ. The paper extracts the angle as
arctan(R_θ(2,2) / R_θ(2,1)); for R_θ = [[cos θ, −sin θ], [sin θ, cos θ]] that ratio is
cot θ, so we take the two-argument arctangent of the same second row, atan2(R_θ(2,1),
R_θ(2,2)), which is θ itself in all four quadrants. Image coordinates: x right, y down, so a
positive θ turns from the x axis towards the y axis (clockwise on screen).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True, eq=False)
class Decomposition:
    """The factors of α T_sift: ``alpha``; ``translation`` (2,) = T; ``rotation`` (2, 2) = R_θ;
    ``axes`` (2, 2) = R_φ; ``scales`` (2,) = diagonal of S_v; ``projective`` (2,) = last row
    of P; ``theta`` (rad), the rotation angle of R_θ."""

    alpha: float
    translation: np.ndarray
    rotation: np.ndarray
    axes: np.ndarray
    scales: np.ndarray
    projective: np.ndarray
    theta: float

    def matrices(self) -> dict[str, np.ndarray]:
        """The 3×3 factors T, R_theta, R_minus_phi, S_v, R_phi, P of the paper's equation."""

        def lift(block: np.ndarray) -> np.ndarray:
            m = np.eye(3)
            m[:2, :2] = block
            return m

        translation = np.eye(3)
        translation[:2, 2] = self.translation
        projective = np.eye(3)
        projective[2, :2] = self.projective
        return {
            "T": translation,
            "R_theta": lift(self.rotation),
            "R_minus_phi": lift(self.axes.T),
            "S_v": lift(np.diag(self.scales)),
            "R_phi": lift(self.axes),
            "P": projective,
        }

    def compose(self) -> np.ndarray:
        """α T_sift (3, 3) rebuilt from the factors: T R_θ R_−φ S_v R_φ P."""
        m = self.matrices()
        return m["T"] @ m["R_theta"] @ m["R_minus_phi"] @ m["S_v"] @ m["R_phi"] @ m["P"]


def decompose(transform: np.ndarray) -> Decomposition:
    """Decompose a 3×3 projective transform T_sift (image to image) into the paper's factors."""
    transform = np.asarray(transform, dtype=float)
    alpha = 1.0 / transform[2, 2]
    normalised = alpha * transform
    projective = normalised[2, :2].copy()
    p_inverse = np.eye(3)
    p_inverse[2, :2] = -projective
    affine = normalised @ p_inverse  # T_A: last row (0, 0, 1)
    u, d, vt = np.linalg.svd(affine[:2, :2])
    if np.linalg.det(u @ vt) < 0:  # a reflection: keep R_θ a rotation, put the sign in S_v
        u[:, 1] *= -1.0
        d = d * np.array([1.0, -1.0])
    rotation = u @ vt
    return Decomposition(
        alpha=float(alpha),
        translation=affine[:2, 2].copy(),
        rotation=rotation,
        axes=vt,
        scales=d,
        projective=projective,
        theta=rotation_angle(rotation),
    )


def rotation_angle(rotation: np.ndarray) -> float:
    """θ (rad, in (−π, π]) of a 2×2 (or 3×3) rotation R_θ, from its second row."""
    return float(np.arctan2(rotation[1, 0], rotation[1, 1]))
