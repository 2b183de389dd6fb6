"""SIFT features φ: where they are, and how they travel through npz files without pickle."""

import numpy as np

from vslsp.vision.features import Features, extract_features, object_features
from vslsp.worlds.house_roof.sprites import houses_world


def test_features_are_found_on_texture_and_not_on_a_blank_board():
    image = houses_world([(100, 100)], [0])
    features = extract_features(image)
    assert len(features) > 10 and features.descriptors.shape == (len(features), 128)
    assert len(extract_features(np.full((120, 160, 3), 200, np.uint8))) == 0


def test_object_features_stay_in_the_box_and_are_in_image_pixels():
    image = houses_world([(100, 100), (300, 200)], [0, 1])
    features = object_features(image, (300, 200, 60, 60))
    assert len(features) > 5
    x, y = features.keypoints[:, 0], features.keypoints[:, 1]
    assert (x > 290).all() and (x < 370).all() and (y > 190).all() and (y < 270).all()


def test_features_round_trip_through_npz_without_pickle(tmp_path):
    features = extract_features(houses_world([(100, 100)], [0]))
    np.savez(tmp_path / "phi.npz", **features.to_arrays("op01"))
    with np.load(tmp_path / "phi.npz", allow_pickle=False) as arrays:
        loaded = Features.from_arrays(arrays, "op01")
    assert np.array_equal(loaded.keypoints, features.keypoints)
    assert np.array_equal(loaded.descriptors, features.descriptors)


def test_a_mask_gives_the_full_image_features_inside_it_in_image_pixels():
    image = houses_world([(100, 100), (300, 200)], [0, 1])
    mask = np.zeros(image.shape[:2], np.uint8)
    mask[190:270, 290:370] = 1
    masked = extract_features(image, mask)
    whole = extract_features(image)
    inside = whole.keypoints[
        (whole.keypoints[:, 0] >= 290)
        & (whole.keypoints[:, 0] < 370)
        & (whole.keypoints[:, 1] >= 190)
        & (whole.keypoints[:, 1] < 270)
    ]
    assert len(masked) >= 0.8 * len(inside) > 5
    x, y = masked.keypoints[:, 0], masked.keypoints[:, 1]
    assert (x >= 289).all() and (x < 371).all() and (y >= 189).all() and (y < 271).all()
    distance = np.linalg.norm(inside[:, None, :2] - masked.keypoints[None, :, :2], axis=2).min(axis=1)
    assert np.mean(distance < 0.5) >= 0.8  # the same keypoints, found in the cut-out
    assert len(extract_features(image, np.zeros_like(mask))) == 0
