"""VSL-3D on rendered RGB-D captures: getObject finds the one object the tutor moved and its
6-DoF motion; findBestMatch finds a recorded observation in a reshuffled world."""

import numpy as np
import pytest

from vslsp.errors import InputError, TaskFailed
from vslsp.sim.cloud_scene import SENSOR, CloudScene
from vslsp.vsl3d.cloud import DepthCamera
from vslsp.vsl3d.registration import transform_error
from vslsp.vsl3d.vsl import CloudObservation, WorldCloud, find_best_match, get_object

from tests.vsl3d.conftest import WORKSPACE

LAYOUT = {"duck": (0.42, -0.17, 0.4), "teddy": (0.62, -0.16, -0.5), "mug": (0.40, 0.03, 2.4),
          "blob": (0.66, 0.0, 1.0)}
TOLERANCE_M, TOLERANCE_DEG = 0.005, 3.0


def _world(scene: CloudScene) -> WorldCloud:
    image = scene.capture()
    return WorldCloud.capture(image.depth, DepthCamera.of(image.camera), WORKSPACE)


def _centre(scene: CloudScene, name: str) -> np.ndarray:
    lower, upper = scene.bounds(name)
    return (lower + upper) / 2.0


def _demonstrate(scene: CloudScene, name: str, x: float, y: float, yaw: float, roll: float = 0.0,
                 pitch: float = 0.0, into_tray: bool = False):
    """The tutor moves ``name``; returns the pre and post worlds, the true motion (4, 4) and the
    object's centre before the move."""
    pre = _world(scene)
    before, centre = scene.pose(name), _centre(scene, name)
    support = scene.surface_height(x, y) if into_tray else 0.0
    scene.tutor_move(name, scene.resting_pose(name, x, y, yaw, roll, pitch, support))
    return pre, _world(scene), scene.pose(name) @ np.linalg.inv(before), centre


def _assert_within_bounds(points: np.ndarray, scene: CloudScene, name: str) -> None:
    lower, upper = scene.bounds(name)
    inside = np.all((points >= lower - 0.003) & (points <= upper + 0.003), axis=1)
    assert inside.mean() > 0.98


def test_get_object_finds_the_moved_object_and_its_planar_motion():
    with CloudScene(LAYOUT) as scene:
        pre_bounds = scene.bounds("teddy")
        pre, post, truth, centre = _demonstrate(scene, "teddy", 0.53, -0.04, 0.3)
        moved = get_object(pre, post)
        _assert_within_bounds(moved.post.points, scene, "teddy")
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
        pre, post, truth, centre = _demonstrate(scene, "duck", 0.56, 0.16, 1.5, roll=0.3, pitch=0.2,
                                                into_tray=True)
        moved = get_object(pre, post)
        _assert_within_bounds(moved.post.points, scene, "duck")
    translation, rotation = transform_error(moved.transform, truth, centre)
    assert translation < TOLERANCE_M and rotation < TOLERANCE_DEG


@pytest.mark.slow
def test_get_object_with_sensor_noise():
    with CloudScene(LAYOUT, noise=True, seed=4) as scene:
        pre, post, truth, centre = _demonstrate(scene, "teddy", 0.53, -0.03, 0.3, pitch=0.15)
        moved = get_object(pre, post, method="sac_ia")
    translation, rotation = transform_error(moved.transform, truth, centre)
    assert translation < TOLERANCE_M and rotation < TOLERANCE_DEG


def test_nothing_moved_is_a_clear_error():
    with CloudScene(LAYOUT, noise=True, seed=1) as scene:
        pre, post = _world(scene), _world(scene)  # two captures, different sensor noise
    with pytest.raises(TaskFailed, match="nothing moved"):
        get_object(pre, post)


def test_several_moved_objects_are_a_clear_error():
    with CloudScene(LAYOUT) as scene:
        pre = _world(scene)
        scene.tutor_move("duck", scene.resting_pose("duck", 0.53, -0.04, 1.0))
        scene.tutor_move("blob", scene.resting_pose("blob", 0.56, 0.16, 0.0, support=scene.surface_height(0.56, 0.16)))
        post = _world(scene)
    with pytest.raises(TaskFailed, match="several objects moved") as error:
        get_object(pre, post)
    assert str(error.value).count("left") == 2 and str(error.value).count("arrived") == 2


def test_find_best_match_finds_a_recorded_observation_in_a_reshuffled_world(tmp_path):
    with CloudScene(LAYOUT) as scene:
        recorded_pose = scene.pose("teddy")  # where the pre-action observation saw it
        pre, post, _, _ = _demonstrate(scene, "teddy", 0.53, -0.04, 0.3)
        observation = get_object(pre, post).pre
    observation.save(tmp_path / "teddy.npz")
    observation = CloudObservation.load(tmp_path / "teddy.npz")
    reshuffled = {"duck": (0.64, -0.02, -1.0), "teddy": (0.45, -0.12, 0.2), "mug": (0.60, -0.18, 1.0),
                  "blob": (0.40, 0.06, 2.5)}
    with CloudScene(reshuffled) as scene:
        world = _world(scene)
        truth = scene.pose("teddy") @ np.linalg.inv(recorded_pose)
        match = find_best_match(world, observation)
        _assert_within_bounds(match.points, scene, "teddy")
    translation, rotation = transform_error(match.registration.transform, truth, observation.centroid)
    assert translation < TOLERANCE_M and rotation < TOLERANCE_DEG
    assert match.frame.contains(match.points).all()


def test_an_absent_object_is_not_matched(duck_view):
    points, sensor = duck_view
    observation = CloudObservation(points, WORKSPACE, sensor)
    with CloudScene({"mug": (0.5, -0.1, 0.0), "blob": (0.62, 0.05, 1.0)}, tray=False) as scene:
        world = _world(scene)
    with pytest.raises(TaskFailed, match="not in this world|fits only"):
        find_best_match(world, observation)


def test_bad_observation_files_and_methods(tmp_path, duck_view):
    (tmp_path / "bad.npz").write_bytes(b"not a zip")
    with pytest.raises(InputError, match="cannot read a VSL-3D observation"):
        CloudObservation.load(tmp_path / "bad.npz")
    points, sensor = duck_view
    world = WorldCloud(points, np.zeros((SENSOR.height, SENSOR.width)), DepthCamera.of(SENSOR))
    with pytest.raises(InputError, match="unknown match-finding method"):
        find_best_match(world, CloudObservation(points, WORKSPACE, sensor), method="magic")
