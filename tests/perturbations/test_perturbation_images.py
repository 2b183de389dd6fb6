"""Perturbations of a reproduction's world (issue 38), on the house-roof board's real renders: level 0
draws and changes nothing, the same seed draws the same, and each operation does what its level says."""

from __future__ import annotations

import numpy as np
import pytest

from vslsp.errors import InputError
from vslsp.perturbations import Perturbation, images, viewpoint
from vslsp.worlds.house_roof.board import HouseWorld


@pytest.fixture(scope="module")
def board() -> np.ndarray:
    return HouseWorld.random(5).render()


def _psnr(a: np.ndarray, b: np.ndarray) -> float:
    return float(10 * np.log10(255.0**2 / np.mean((a.astype(float) - b) ** 2)))


def test_level_zero_draws_nothing_and_leaves_the_image(board):
    drawn = Perturbation().draw(5)
    assert drawn.none and drawn.to_dict() == {} and images.apply(board, drawn, 0) is board
    assert np.allclose(viewpoint.board_homography(960, 720, 1200.0, drawn, 1000.0), np.eye(3))


def test_the_same_seed_draws_the_same_and_another_seed_differs(board):
    levels = Perturbation.parse(["camera=10", "brightness=40", "noise=8"])
    first, again, other = levels.draw(7), levels.draw(7), levels.draw(8)
    assert first == again and first != other
    assert np.array_equal(images.apply(board, first, 0), images.apply(board, again, 0))
    assert not np.array_equal(images.apply(board, first, 0), images.apply(board, first, 1))  # each image its own noise
    assert first.to_dict()["kinds"] == ["camera", "light", "noise"]


@pytest.mark.parametrize(
    ("items", "says"),
    [
        (["camera=40"], "camera=0 to 15"),
        (["blur=3"], "NAME one of"),
        (["noise=eight"], "must be a number"),
        (["clutter=1.5"], "whole number"),
        (["noise"], "NAME=LEVEL"),
    ],
)
def test_a_bad_level_is_refused_with_what_to_give(items, says):
    with pytest.raises(InputError, match=says):
        Perturbation.parse(items)


def test_brightness_scales_the_light_by_its_level(board):
    dark = (board // 2).astype(np.uint8)  # nothing clips at +40 %
    for seed in range(4):
        drawn = Perturbation(brightness=40).draw(seed)
        out = images.apply(dark, drawn, 0).astype(float)
        ratio = np.median(out[dark > 20] / dark[dark > 20])
        assert ratio == pytest.approx(drawn.brightness, abs=0.02) and drawn.brightness in (
            pytest.approx(0.6),
            pytest.approx(1.4),
        )


def test_colour_temperature_warms_or_cools_and_keeps_the_luma(board):
    dim = (board // 2).astype(np.uint8)  # no channel clips
    background = dim[5:60, 5:60].reshape(-1, 3).astype(float).mean(axis=0)
    for kelvin, redder in ((3000, True), (8000, False)):
        out = images.apply(dim, Perturbation(temperature=kelvin).draw(1), 0)[5:60, 5:60].reshape(-1, 3).mean(axis=0)
        assert bool(out[0] / out[2] > background[0] / background[2] * 1.1) is redder
        assert bool(out[2] / out[0] > background[2] / background[0] * 1.1) is not redder
        assert float(images.LUMA @ out) == pytest.approx(float(images.LUMA @ background), rel=0.04)


def test_gaussian_noise_has_its_sigma_and_jpeg_loses_with_its_quality(board):
    grey = np.full_like(board, 120)
    noisy = images.apply(grey, Perturbation(noise=8).draw(3), 0).astype(float) - 120
    assert noisy.std() == pytest.approx(8.0, abs=0.2) and abs(noisy.mean()) < 0.1
    coarse = images.apply(board, Perturbation(jpeg=20).draw(3), 0)
    fine = images.apply(board, Perturbation(jpeg=90).draw(3), 0)
    assert 25 < _psnr(board, coarse) < _psnr(board, fine)


def test_salt_and_pepper_and_depth_holes_hit_their_share(board):
    grey = np.full_like(board, 120)
    hit = np.any(images.apply(grey, Perturbation(salt=0.05).draw(2), 0) != 120, axis=2).mean()
    assert hit == pytest.approx(0.05, abs=0.005)
    depth = np.full((480, 640), 0.8, np.float32)
    holes = images.depth_holes(depth, 0.1, np.random.default_rng(0))
    assert 0.06 < float((holes == 0).mean()) < 0.1
    noisy = images.depth_noise(holes, 0.004, np.random.default_rng(0))
    assert np.all(noisy[holes == 0] == 0) and np.std(noisy[holes > 0] - 0.8) == pytest.approx(0.004, rel=0.05)


def test_a_shadow_darkens_a_band_by_its_strength():
    factors = images.shadow_band((720, 960), 0.5, 0.3, 0.0)
    assert factors.min() == pytest.approx(0.5, abs=0.01) and factors.max() == pytest.approx(1.0)
    assert 0.1 < float((factors < 0.99).mean()) < 0.35  # a band, not the view


def test_occlusion_hides_its_share_of_the_box(board):
    box = (100.0, 100.0, 220.0, 180.0)
    out = images.occlude(board, box, 0.25, np.pi / 2, np.random.default_rng(0))
    changed = np.any(out != board, axis=2)
    assert changed[100:180, 100:220].mean() == pytest.approx(0.25, abs=0.03) and not changed[:100].any()
    assert changed[160:180, 100:220].all()  # from below (side pi/2: +v)


def test_the_moved_camera_sees_the_board_and_its_calibration_maps_it_back(board):
    drawn = Perturbation(camera=10, scale=0.8).draw(5)
    homography = viewpoint.board_homography(960, 720, 1200.0, drawn, 1000.0)
    seen = viewpoint.view(board, homography)
    assert _psnr(board, seen) < 20  # the view really moved
    back = viewpoint.to_board(seen, homography)
    assert _psnr(board[100:620, 100:860], back[100:620, 100:860]) > 27  # mapped back, resampling aside


def test_scale_brings_the_camera_nearer_about_the_centre():
    homography = viewpoint.board_homography(960, 720, 1200.0, Perturbation(scale=1.25).draw(0), 1000.0)
    u, v, w = homography @ np.array([480.0 + 100.0, 360.0, 1.0])
    assert (u / w, v / w) == (pytest.approx(480.0 + 125.0), pytest.approx(360.0))
