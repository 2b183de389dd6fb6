"""VSL-3D's findBestMatch: a recorded observation is found in a reshuffled world and its pose
recovered; an absent object is not matched."""

import re

import numpy as np
import pytest
from helpers.vsl3d import LAYOUT, TOLERANCE_DEG, TOLERANCE_M, WORKSPACE, assert_within_bounds, demonstrate, world

from vslsp.errors import InputError
from vslsp.outcomes import NoMatch
from vslsp.sim.cloud_scene import SENSOR, CloudScene
from vslsp.vsl3d.cloud import DepthCamera
from vslsp.vsl3d.matching import CloudMatch, find_best_match, object_windows
from vslsp.vsl3d.registration import transform_error
from vslsp.vsl3d.vsl import CloudObservation, WorldCloud, get_object


def test_find_best_match_finds_a_recorded_observation_in_a_reshuffled_world(tmp_path):
    with CloudScene(LAYOUT) as scene:
        recorded_pose = scene.pose("teddy")  # where the pre-action observation saw it
        pre, post, _, _ = demonstrate(scene, "teddy", 0.53, -0.04, 0.3)
        observation = get_object(pre, post).pre
    observation.save(tmp_path / "teddy.npz")
    observation = CloudObservation.load(tmp_path / "teddy.npz")
    reshuffled = {
        "duck": (0.64, -0.02, -1.0),
        "teddy": (0.45, -0.12, 0.2),
        "mug": (0.60, -0.18, 1.0),
        "blob": (0.40, 0.06, 2.5),
    }
    with CloudScene(reshuffled) as scene:
        captured = world(scene)
        truth = scene.pose("teddy") @ np.linalg.inv(recorded_pose)
        match = find_best_match(captured, observation)
        assert isinstance(match, CloudMatch), match
        assert_within_bounds(match.points, scene, "teddy")
    translation, rotation = transform_error(match.registration.transform, truth, observation.centroid)
    assert translation < TOLERANCE_M and rotation < TOLERANCE_DEG
    assert match.frame.contains(match.points).all()


def test_an_absent_object_is_not_matched(duck_view):
    points, sensor = duck_view
    observation = CloudObservation(points, WORKSPACE, sensor)
    with CloudScene({"mug": (0.5, -0.1, 0.0), "blob": (0.62, 0.05, 1.0)}, tray=False) as scene:
        captured = world(scene)
    found = find_best_match(captured, observation)
    assert isinstance(found, NoMatch) and not found  # a typed outcome, as 2-D match finding's
    assert re.search(r".+; nor in any of 2 object-sized windows of the world$", found.reason), found.reason


def test_bad_observation_files_and_methods(tmp_path, duck_view):
    (tmp_path / "bad.npz").write_bytes(b"not a zip")
    with pytest.raises(InputError, match="cannot read a VSL-3D observation"):
        CloudObservation.load(tmp_path / "bad.npz")
    points, sensor = duck_view
    empty = WorldCloud(points, np.zeros((SENSOR.height, SENSOR.width)), DepthCamera.of(SENSOR))
    with pytest.raises(InputError, match="unknown match-finding method"):
        find_best_match(empty, CloudObservation(points, WORKSPACE, sensor), method="magic")


def test_windows_are_the_objects_not_the_box(duck_view):
    layout = {"duck": (0.45, -0.15, 0.3), "teddy": (0.62, -0.12, 1.0)}
    with CloudScene(layout) as scene:
        scene.tutor_move(
            "teddy", scene.resting_pose("teddy", 0.56, 0.16, 0.5, support=scene.surface_height(0.56, 0.16))
        )
        captured = world(scene)
        centres = [np.mean(scene.bounds(name), axis=0) for name in layout]
    found = [centre for _, centre in object_windows(captured.points, duck_view[0])]
    assert len(found) == 2  # the tray is too large to be a window; the teddy in it is one
    for centre in centres:
        assert min(np.linalg.norm(f[:2] - centre[:2]) for f in found) < 0.03
