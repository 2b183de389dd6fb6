"""The cheaper iCub world gives the same answers: the simulated (frozen, hand-only collision)
robot keeps the kinematics, the batched scene sampler places cubes where the reference check
does, a view of an unchanged world is the view rendered, textures are seeded, and a trial's
result does not depend on the trials run before it in the process."""

from __future__ import annotations

import numpy as np
import pytest

from vslsp.sim import LineWorld
from vslsp.sim.icub import HEAD_POSE, IK_JOINTS
from vslsp.sim.quiet import quiet
from vslsp.sim.scene import LandmarkSpec, _along_span, _placeable
from vslsp.sim.textures import cube_atlas

with quiet():
    import pybullet as pb


def _reference_span(landmark: LandmarkSpec, far: np.ndarray, across: np.ndarray):
    """The span as first written: every cube on its own grid, through _placeable."""
    grid = np.linspace(-0.2, 0.2, 81)
    low, high = -np.inf, np.inf
    for f, a in zip(far, across, strict=True):
        centres = landmark.point + np.outer(grid, landmark.direction) + a * landmark.normal
        ok = grid[_placeable(landmark, np.full(len(grid), f), centres)]
        if len(ok) == 0:
            return None
        low, high = max(low, ok.min()), min(high, ok.max())
    return (float(low), float(high)) if low < high else None


def test_the_batched_span_is_the_reference_span():
    rng = np.random.default_rng(0)
    found = 0
    for _ in range(3000):
        landmark = LandmarkSpec(x=float(rng.uniform(0.2, 0.25)), angle=float(rng.uniform(-0.35, 0.35)))
        n = int(rng.integers(1, 5))
        far = rng.random(n) < 0.5
        across = rng.uniform(0.03, 0.09, size=n) * np.where(far, 1.0, -1.0)
        span = _along_span(landmark, far, across)
        assert span == _reference_span(landmark, far, across)
        found += span is not None
    assert found > 300  # both outcomes are exercised


def test_the_simulated_robot_keeps_the_kinematics():
    with LineWorld(seed=1) as world:
        robot = world.robot
        rng = np.random.default_rng(2)
        kinematics = robot.kinematics
        for _ in range(5):
            q = rng.uniform(kinematics.ik_lower, kinematics.ik_upper)
            for index, value in zip(robot.ik_indices, q, strict=True):
                pb.resetJointState(robot.body, index, value, physicsClientId=world.client)
            kinematics.set_ik_joints(q)
            position, rotation = robot.hand_pose()
            expected_position, expected_rotation = kinematics.hand_pose()
            assert np.allclose(position, expected_position, atol=1e-9)
            assert np.allclose(rotation, expected_rotation, atol=1e-9)
        # the frozen head looks where the kinematic head at HEAD_POSE looks
        kinematics.set_joints(HEAD_POSE)
        head = kinematics.link_index["head"]
        sim = pb.getLinkState(robot.body, head, computeForwardKinematics=True, physicsClientId=world.client)
        kin = pb.getLinkState(kinematics.body, head, computeForwardKinematics=True, physicsClientId=kinematics.client)
        assert np.allclose(sim[4], kin[4], atol=1e-9) and np.allclose(sim[5], kin[5], atol=1e-9)
        movable = [
            i
            for i in range(pb.getNumJoints(robot.body, physicsClientId=world.client))
            if pb.getJointInfo(robot.body, i, physicsClientId=world.client)[2] != pb.JOINT_FIXED
        ]
        assert sorted(movable) == sorted(robot.ik_indices) and len(movable) == len(IK_JOINTS)


def test_a_view_of_an_unchanged_world_is_the_rendered_view():
    with LineWorld(seed=4) as world, LineWorld(seed=4) as twin:
        first = world.observe("head")
        again = world.observe("head")
        assert np.array_equal(first.rgb, again.rgb) and np.array_equal(first.depth, again.depth)
        again.rgb[:] = 0  # a caller's copy: the next view is unharmed
        assert np.array_equal(world.observe("head").rgb, first.rgb)
        assert np.array_equal(twin.observe("head").rgb, first.rgb)  # same seed, same pixels
        cube = world.spec.cubes[0]
        x, y, _ = world.cube_pose(cube.name)
        world.tutor.relocate(cube.name, x + 0.03, y)
        moved = world.observe("head")
        assert not np.array_equal(moved.rgb, first.rgb)
        assert not np.array_equal(world.observe("head", 320, 240).rgb, twin.observe("head", 320, 240).rgb)


def test_cube_textures_are_seeded_by_name():
    red = (0.85, 0.1, 0.1)
    assert np.array_equal(cube_atlas(red, "red"), cube_atlas(red, "red"))
    assert not np.array_equal(cube_atlas(red, "red"), cube_atlas(red, "red_2"))
    atlas = cube_atlas(red, "red")
    faces = [atlas[r * 48 : (r + 1) * 48, c * 48 : (c + 1) * 48] for r in range(2) for c in range(3)]
    assert all(not np.array_equal(a, b) for i, a in enumerate(faces) for b in faces[i + 1 :])


@pytest.mark.slow
def test_a_trial_does_not_depend_on_the_trials_before_it():
    from helpers.records import without_times

    from vslsp.tasks import get_task

    task = get_task("simple-vsl-task")
    first = without_times(task.run_trial(3).to_dict())
    task.run_trial(4)
    again = without_times(task.run_trial(3).to_dict())
    assert first == again and first["success"]
