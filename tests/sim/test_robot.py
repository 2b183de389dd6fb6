"""The iCub's right arm in Cartesian space: IK reach, unreachable targets, kinesthetic demos."""

import numpy as np
import pytest

from vslsp.errors import UnreachableError
from vslsp.sim import TABLE_Z, CubeSpec, LandmarkSpec, LineWorld, SceneSpec
from vslsp.sim.icub import KinematicICub, palm_down_rotation
from vslsp.sim.robot import HAND_YAW, _reach_seed


@pytest.fixture(scope="module")
def world():
    spec = SceneSpec((CubeSpec("blue", "blue", 0.30, 0.02),), LandmarkSpec(0.22, 0.0))
    with LineWorld(spec) as world:
        yield world


def test_ik_reaches_targets_over_the_table_within_1_cm():
    kinematics = KinematicICub()
    rng = np.random.default_rng(0)
    targets = np.column_stack(
        [
            rng.uniform(0.12, 0.42, 40),
            rng.uniform(-0.24, 0.02, 40),
            np.full(40, TABLE_Z + 0.02),
        ]
    )
    errors = [kinematics.solve(t, palm_down_rotation(HAND_YAW), _reach_seed()).position_error for t in targets]
    kinematics.close()
    assert np.max(errors) < 0.01
    assert np.median(errors) < 1e-3


def test_the_simulated_hand_follows_a_path(world):
    path = np.linspace([0.15, -0.15, TABLE_Z + 0.04], [0.28, -0.05, TABLE_Z + 0.04], 30)
    world.robot.move_hand(path)
    assert np.linalg.norm(world.robot.hand_position() - path[-1]) < 0.01


def test_an_unreachable_target_is_a_clear_error_before_moving(world):
    before = world.robot.hand_position()
    with pytest.raises(UnreachableError, match="cannot reach"):
        world.robot.move_hand(np.array([[0.9, -0.6, TABLE_Z]]))
    assert np.linalg.norm(world.robot.hand_position() - before) < 1e-3


def test_a_kinesthetic_demonstration_starts_and_ends_where_asked_and_is_smooth(world):
    via = np.array([[0.16, -0.18, TABLE_Z + 0.06], [0.22, -0.12, TABLE_Z + 0.05], [0.26, -0.06, TABLE_Z + 0.03]])
    demo = world.tutor.kinesthetic(via, duration=1.5, seed=3)
    assert demo.t[1] - demo.t[0] <= 0.01  # >= 100 Hz
    assert np.linalg.norm(demo.position[0] - via[0]) < 0.01
    assert np.linalg.norm(demo.position[-1] - via[-1]) < 0.01
    jerk = np.gradient(demo.acceleration, demo.t, axis=0)
    assert np.percentile(np.linalg.norm(jerk, axis=1), 95) < 200.0  # m/s^3


def test_parking_takes_the_arm_out_of_the_table_area(world):
    world.robot.park()
    hand = world.robot.hand_position()
    assert hand[2] < TABLE_Z  # beside the body, below the table top
