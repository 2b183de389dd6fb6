"""Grasping from the point cloud and the robot's pick-and-place in the physical VSL-3D world:
the grasp comes from the cloud (never the simulator), the Panda carries the object by the
demanded motion, and bad input (nothing in view, an object never seen, out of reach, too wide)
is a diagnosis, not a traceback."""

import numpy as np
import pytest

from vslsp.errors import TaskFailed
from vslsp.experiments.cloud_reproduction import execute_grasp, reproduce, world_of
from vslsp.sim.cloud_scene import CloudScene
from vslsp.sim.panda import FINGER_OPEN
from vslsp.vsl3d.grasping import Grasp, place_for, plan_grasp
from vslsp.vsl3d.registration import transform_error
from vslsp.vsl3d.vsl import CloudObservation
from vslsp.worlds.rgbd_table import RgbdTable


def _object_points(scene: CloudScene, name: str) -> np.ndarray:
    points = world_of(scene.capture()).points
    lower, upper = scene.bounds(name)
    return points[np.all((points >= lower - 0.005) & (points <= upper + 0.005), axis=1)]


def test_the_grasp_comes_from_the_cloud_and_fits_the_gripper():
    with RgbdTable({"duck": (0.5, -0.1, 0.6)}, tray=False, robot=True) as scene:
        points = _object_points(scene, "duck")
        lower, upper = scene.bounds("duck")
    grasp = plan_grasp(points, FINGER_OPEN)
    assert np.all(grasp.point[:2] > lower[:2]) and np.all(grasp.point[:2] < upper[:2])
    assert 0.0 < grasp.point[2] < grasp.top <= upper[2] + 0.003
    assert grasp.width <= 2 * FINGER_OPEN


def test_a_box_wider_than_the_gripper_is_ungraspable():
    rng = np.random.default_rng(0)
    top = np.column_stack([rng.uniform(0.4, 0.52, 2000), rng.uniform(-0.06, 0.06, 2000), np.full(2000, 0.05)])
    with pytest.raises(TaskFailed, match="ungraspable"):
        plan_grasp(top, FINGER_OPEN)


def test_the_place_applies_the_motion_to_the_grasp():
    grasp = Grasp(np.array([0.5, 0.0, 0.04]), 0.3, 0.04, 0.07)
    motion = np.eye(4)
    motion[:2, :2] = [[0.0, -1.0], [1.0, 0.0]]  # a quarter turn about z, then 10 cm along y
    motion[:3, 3] = [0.0, 0.1, 0.0]
    point, theta = place_for(grasp, motion)
    np.testing.assert_allclose(point[:2], [0.0, 0.6])
    assert theta == pytest.approx(0.3 + np.pi / 2)


@pytest.mark.slow
def test_the_robot_carries_the_object_by_the_motion():
    with RgbdTable({"duck": (0.45, -0.1, 0.3)}, tray=False, robot=True) as scene:
        before = scene.pose("duck")
        grasp = plan_grasp(_object_points(scene, "duck"), FINGER_OPEN)
        motion = np.eye(4)
        motion[:2, :2] = [[np.cos(0.5), -np.sin(0.5)], [np.sin(0.5), np.cos(0.5)]]
        motion[:3, 3] = [0.6, 0.1, 0.0] - motion[:3, :3] @ np.array([0.45, -0.1, 0.0])
        result = execute_grasp(scene, grasp, motion, list(scene.bodies.values()))
        scene.settle()
        lower, upper = scene.bounds("duck")
        offset, turn = transform_error(motion @ before, scene.pose("duck"), (lower + upper) / 2.0)
    assert result.ok and result.held == "duck"
    assert offset < 0.015 and turn < 15.0


def test_an_object_out_of_reach_is_diagnosed():
    with RgbdTable({"duck": (0.5, 0.0, 0.0)}, tray=False, robot=True) as scene:
        grasp = Grasp(np.array([1.2, 0.0, 0.04]), 0.0, 0.04, 0.07)
        result = execute_grasp(scene, grasp, np.eye(4), list(scene.bodies.values()))
    assert not result.ok and result.diagnosis == "unreachable"


def test_an_empty_capture_is_a_diagnosis_not_a_traceback(duck_view):
    points, sensor = duck_view
    observation = CloudObservation(points, None, sensor)  # type: ignore[arg-type]
    with RgbdTable({}, tray=False, robot=True) as scene:
        record = reproduce(
            scene, observation, lambda match, world: np.eye(4), method="prerejective_ransac", seed=0, movable=[]
        )
    assert record.diagnosis is not None and record.diagnosis.startswith("empty capture")
    assert record.to_dict()["executed_by"] == "robot" and record.to_dict()["attempts"] == 1


@pytest.mark.slow
def test_an_object_never_seen_is_a_diagnosis(duck_view):
    points, sensor = duck_view
    observation = CloudObservation(points, None, sensor)  # type: ignore[arg-type]
    with RgbdTable({"blob": (0.5, 0.0, 0.0), "mug": (0.45, -0.15, 1.0)}, robot=True) as scene:
        record = reproduce(
            scene,
            observation,
            lambda match, world: np.eye(4),
            method="prerejective_ransac",
            seed=0,
            movable=list(scene.bodies.values()),
        )
    assert record.diagnosis is not None and "match" in record.diagnosis


@pytest.mark.slow
@pytest.mark.parametrize(
    ("x", "y", "yaw"),
    [(0.45, 0.0, -1.047), (0.58, 0.0, 1.047), (0.58, 0.15, -1.047), (0.68, -0.2, 0.0), (0.68, -0.2, -2.094)],
)
def test_the_duckling_is_held_at_its_widest(x, y, yaw):
    """The 5.5 cm duckling gripped 3 cm under its top (below half its height) wedged under the
    pads against the table: 12 of 54 placements failed, 16 of 100 table-cleaning trials needed
    a second grasp. Gripped at half its seen height, these (all failures then) are held and
    carried."""
    with RgbdTable({"duckling": (x, y, yaw)}, tray=False, robot=True) as scene:
        points = _object_points(scene, "duckling")
        grasp = plan_grasp(points, FINGER_OPEN)
        bottom, top = np.percentile(points[:, 2], [0.5, 99.5])
        assert grasp.point[2] == pytest.approx((bottom + top) / 2.0, abs=0.002)
        motion = np.eye(4)
        motion[:3, 3] = [0.0, 0.08 if y < 0 else -0.08, 0.0]
        result = execute_grasp(scene, grasp, motion, list(scene.bodies.values()))
        assert result.ok, result.diagnosis
        assert result.held == "duckling"
