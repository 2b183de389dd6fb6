"""VSL-3D's getObject on rendered RGB-D captures: it finds the one object the tutor moved, its
pre-/post-action observations and its 6-DoF motion, or says clearly why not."""

import numpy as np
import pytest
from helpers.vsl3d import LAYOUT, TOLERANCE_DEG, TOLERANCE_M, assert_within_bounds, demonstrate, world

from vslsp.errors import TaskFailed
from vslsp.sim.cloud_scene import CloudScene
from vslsp.vsl3d.registration import transform_error
from vslsp.vsl3d.vsl import get_object


def test_get_object_finds_the_moved_object_and_its_planar_motion():
    with CloudScene(LAYOUT) as scene:
        pre_bounds = scene.bounds("teddy")
        pre, post, truth, centre = demonstrate(scene, "teddy", 0.53, -0.04, 0.3)
        moved = get_object(pre, post)
        assert_within_bounds(moved.post.points, scene, "teddy")
    inside = np.all((moved.pre.points >= pre_bounds[0] - 0.003) & (moved.pre.points <= pre_bounds[1] + 0.003), axis=1)
    assert inside.mean() > 0.98
    translation, rotation = transform_error(moved.transform, truth, centre)
    assert translation < TOLERANCE_M and rotation < TOLERANCE_DEG
    assert moved.pre.frame.contains(moved.pre.points).all()
    summary = moved.to_dict()
    assert summary["rotation_deg"] == pytest.approx(np.degrees(0.8), abs=TOLERANCE_DEG)
    assert summary["fitness"] > 0.6


@pytest.mark.slow
def test_get_object_recovers_a_tilted_placement_in_the_tray():
    with CloudScene(LAYOUT) as scene:
        pre, post, truth, centre = demonstrate(scene, "duck", 0.56, 0.16, 1.5, roll=0.3, pitch=0.2, into_tray=True)
        moved = get_object(pre, post)
        assert_within_bounds(moved.post.points, scene, "duck")
    translation, rotation = transform_error(moved.transform, truth, centre)
    assert translation < TOLERANCE_M and rotation < TOLERANCE_DEG


@pytest.mark.slow
def test_get_object_with_sensor_noise():
    with CloudScene(LAYOUT, noise=True, seed=4) as scene:
        pre, post, truth, centre = demonstrate(scene, "teddy", 0.53, -0.03, 0.3, pitch=0.15)
        moved = get_object(pre, post, method="sac_ia")
    translation, rotation = transform_error(moved.transform, truth, centre)
    assert translation < TOLERANCE_M and rotation < TOLERANCE_DEG


def test_nothing_moved_is_a_clear_error():
    with CloudScene(LAYOUT, noise=True, seed=1) as scene:
        pre, post = world(scene), world(scene)  # two captures, different sensor noise
    with pytest.raises(TaskFailed, match="nothing moved"):
        get_object(pre, post)


def test_several_moved_objects_are_a_clear_error():
    with CloudScene(LAYOUT) as scene:
        pre = world(scene)
        scene.tutor_move("duck", scene.resting_pose("duck", 0.53, -0.04, 1.0))
        scene.tutor_move("blob", scene.resting_pose("blob", 0.56, 0.16, 0.0, support=scene.surface_height(0.56, 0.16)))
        post = world(scene)
    with pytest.raises(TaskFailed, match="several objects moved") as error:
        get_object(pre, post)
    assert str(error.value).count("left") == 2 and str(error.value).count("arrived") == 2
