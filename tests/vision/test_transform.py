"""The decomposition α T_sift = T R_θ R_−φ S_v R_φ P and the rotation angle."""

import numpy as np
import pytest

from vslsp.vision.transform import decompose, rotation_angle


def _similarity(theta, scale, tx, ty):
    c, s = scale * np.cos(theta), scale * np.sin(theta)
    return np.array([[c, -s, tx], [s, c, ty], [0.0, 0.0, 1.0]])


@pytest.mark.parametrize("theta", [-2.5, -0.4, 0.0, 0.3, 1.7, 3.0])
def test_a_similarity_gives_back_its_angle_scale_and_translation(theta):
    d = decompose(3.0 * _similarity(theta, 1.2, 40.0, -7.0))
    assert d.theta == pytest.approx(theta, abs=1e-9)
    assert d.scales == pytest.approx([1.2, 1.2])
    assert d.translation == pytest.approx([40.0, -7.0])
    assert d.alpha == pytest.approx(1 / 3.0)
    assert d.projective == pytest.approx([0.0, 0.0])


def test_the_factors_multiply_back_to_the_normalised_transform():
    transform = _similarity(0.6, 1.0, 12.0, 5.0) @ np.array([[1.3, 0.2, 0], [0.1, 0.8, 0], [0, 0, 1]])
    transform[2, :2] = [2e-4, -1e-4]
    transform *= 0.5
    d = decompose(transform)
    assert d.compose() == pytest.approx(transform / transform[2, 2])
    m = d.matrices()
    assert m["R_minus_phi"] @ m["R_phi"] == pytest.approx(np.eye(3))
    assert np.linalg.det(m["R_theta"][:2, :2]) == pytest.approx(1.0)
    assert np.diag(m["S_v"])[:2] == pytest.approx(d.scales)


def test_a_mirrored_transform_keeps_a_proper_rotation_and_a_negative_scale():
    d = decompose(np.diag([1.0, -1.0, 1.0]) @ _similarity(0.3, 1.0, 0, 0))
    assert np.linalg.det(d.rotation) == pytest.approx(1.0)
    assert np.prod(d.scales) == pytest.approx(-1.0)
    assert d.compose() == pytest.approx(np.diag([1.0, -1.0, 1.0]) @ _similarity(0.3, 1.0, 0, 0))


def test_the_angle_comes_from_the_second_row_of_the_rotation():
    # The paper's arctan(R(2,2) / R(2,1)) is cot θ's arctangent, π/2 − θ; we return θ.
    # The literal formula also loses the quadrant; ours holds over the whole circle.
    for theta in np.linspace(-3.0, 3.0, 13):
        rotation = _similarity(theta, 1.0, 0, 0)[:2, :2]
        assert rotation_angle(rotation) == pytest.approx(theta)
        assert rotation_angle(2.5 * rotation) == pytest.approx(theta)  # a scaled rotation: the same angle
