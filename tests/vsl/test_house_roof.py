"""The house-and-roof simulation of the paper: the tutor puts two roofs on their bodies and the
third below its body; in a new random world VSL reproduces it with the adaptive frame, while a
fixed small frame puts the third roof below a house that already has its roof. Judged on the
generator's ground truth."""

import json

import numpy as np
import pytest
from helpers.cli import vslsp

from vslsp.errors import InputError
from vslsp.experiments.house_roof_trial import PIXEL_SIZE, demonstrate, reproduce
from vslsp.geometry.poses import compose, relative, wrap
from vslsp.tasks import get_task
from vslsp.worlds.house_roof.board import BELOW, TOP, HouseWorld
from vslsp.worlds.house_roof.sprites import body_sprite, houses_world, paste, roof_sprite

# Trials whose new world makes the fixed small frame go wrong (found by running the trials;
# about three in four do): ops 1 and 2 land on free bodies, op 3 below an occupied one.
FIXED_FRAME_FAILS = (1, 4)


@pytest.fixture(scope="module")
def demo():
    return demonstrate(0)


def test_sprites_composite_like_the_drawn_houses():
    image = houses_world([], [], size=(480, 360), seed=1)
    paste(image, body_sprite(), (200.0, 200.0, 0.0))
    paste(image, roof_sprite(), compose((200.0, 200.0, 0.0), TOP))
    drawn = houses_world([(170, 170)], [0], size=(480, 360), seed=1)
    body = (slice(172, 230), slice(170, 230))  # below the roof's edge line
    assert np.array_equal(image[body], drawn[body])  # the body is the drawn one, pixel for pixel
    roof = image[139:170, 170:230].astype(int)
    assert (np.abs(roof - image[5:36, 5:65].astype(int)).sum(axis=2) > 60).mean() > 0.4  # a roof sits on it


def test_the_demonstration_is_recorded_operation_by_operation(demo):
    operations = demo.demonstration.operations
    assert len(operations) == 3 and len(demo.pre_place) == 3
    before, after = demo.world_before, demo.world_after
    for k, op in enumerate(operations):
        # The recorder found the moved roof where the tutor took it from and put it.
        assert np.hypot(op.pose_pre.x - before.roofs[k][0], op.pose_pre.y - before.roofs[k][1]) < 3.0
        assert np.hypot(op.pose_post.x - after.roofs[k][0], op.pose_post.y - after.roofs[k][1]) < 3.0
        # The perceived turn is the tutor's, within half a degree.
        assert abs(wrap(demo.turns[k] - (after.roofs[k][2] - before.roofs[k][2]))) < np.radians(0.5)
    placed = np.array([relative(after.bodies[k], after.roofs[k]) for k in range(3)])
    expected = np.array([TOP, TOP, BELOW])
    assert placed[:, :2] == pytest.approx(expected[:, :2], abs=1e-9)
    assert [wrap(a) for a in placed[:, 2] - expected[:, 2]] == pytest.approx([0.0] * 3, abs=1e-9)
    assert after.goal_reached()


def test_the_judge_wants_one_roof_per_house_in_the_demonstrated_places():
    bodies = ((200.0, 200.0, 0.3), (500.0, 300.0, -1.0), (750.0, 200.0, 2.0))
    right = HouseWorld(bodies, (compose(bodies[0], TOP), compose(bodies[1], BELOW), compose(bodies[2], TOP)))
    assert right.goal_reached()
    doubled = HouseWorld(bodies, (compose(bodies[0], TOP), compose(bodies[0], BELOW), compose(bodies[2], TOP)))
    assert not doubled.goal_reached()  # the paper's wrong reproduction: two roofs on one house
    turned = right.with_roof(1, compose(bodies[1], (0.0, 40.0, np.pi + 0.2)))
    shifted = right.with_roof(1, compose(bodies[1], (8.0, 40.0, np.pi)))
    assert not turned.goal_reached() and not shifted.goal_reached()
    all_on_top = HouseWorld(bodies, tuple(compose(b, TOP) for b in bodies))
    assert not all_on_top.goal_reached()  # not what was demonstrated


def test_random_worlds_are_seeded():
    assert HouseWorld.random(3) == HouseWorld.random(3) != HouseWorld.random(4)
    assert np.array_equal(HouseWorld.random(3).render(), HouseWorld.random(3).render())


def test_the_adaptive_frame_reproduces_the_demonstration_in_a_new_world(demo):
    world = HouseWorld.random(7)
    reproduction = reproduce(demo, world, "adaptive")
    assert [op.diagnosis for op in reproduction.operations] == ["ok", "ok", "ok"]
    assert reproduction.success and reproduction.world_after.goal_reached()
    assert sorted(slots[0] for slots in reproduction.world_after.houses().values()) == ["below", "top", "top"]
    for op in reproduction.operations:
        # The hand's trajectory runs rest -> pick -> place -> rest through the matched points,
        # turning from theta_pick to theta_place; the roof lands where the hand ends.
        pick, place = op.trajectory.key_points[1], op.trajectory.key_points[2]
        assert pick[:2] == pytest.approx(np.array([op.pick.x, op.pick.y]) * PIXEL_SIZE)
        assert place[:2] == pytest.approx(np.array([op.place.x, op.place.y]) * PIXEL_SIZE)
        segments = op.trajectory.segments
        assert op.trajectory.theta[segments[1]] == pytest.approx(op.theta_pick)
        assert op.trajectory.theta[segments[2]] == pytest.approx(op.theta_place)
        assert op.slot[2] < 4.0 and op.slot[3] < np.radians(2.0)  # within 4 px and 2 degrees of the slot


@pytest.mark.slow
@pytest.mark.parametrize("seed", FIXED_FRAME_FAILS)
def test_a_fixed_small_frame_puts_the_third_roof_below_a_finished_house(seed):
    trial = get_task("house-roof").run_trial(seed)
    fixed, adaptive = trial.details["fixed"], trial.details["adaptive"]
    assert [op["diagnosis"] for op in fixed["operations"]] == ["ok", "ok", "wrong place"]
    third = fixed["operations"][2]
    assert third["slot"] == "below" and third["place"]["ambiguous"]  # the right shape, the wrong house
    assert not fixed["success"] and sorted(fixed["houses"][str(third["body"])]) == ["below", "top"]
    assert adaptive["success"] and trial.success
    assert adaptive["operations"][2]["place"]["frame"] > fixed["operations"][2]["place"]["frame"]


@pytest.mark.slow
def test_the_command_writes_the_report_and_prints_json(tmp_path, capsys):
    code, out, _ = vslsp(
        capsys, "experiment", "house-roof", "--trials", 1, "--seed", FIXED_FRAME_FAILS[0], "--json", "--out", tmp_path
    )
    data = json.loads(out)
    assert code == 0
    assert data["experiment"] == "house-roof" and data["trials"] == 1 and data["success_rate"] == 1.0
    assert data["fixed_frame"]["successes"] == 0 and data["adaptive_frame"]["operations_ok"] == 3
    report = json.loads((tmp_path / "report.json").read_text())
    assert report["results"][0]["seed"] == FIXED_FRAME_FAILS[0]
    assert report["results"][0]["adaptive"]["operations"][2]["position_error_px"] < 6.0
    assert "| fixed | 0/1 |" in (tmp_path / "report.md").read_text()
    for name in ("demonstration", "matches_fixed", "matches_adaptive", "final_worlds", "trajectory"):
        assert (tmp_path / report["shown_trial"][name]).stat().st_size > 10_000


def test_bad_input_is_a_clear_error(capsys):
    code, _, err = vslsp(capsys, "experiment", "house-roof", "--trials", "0")
    assert code == 2 and "--trials" in err
    code, _, err = vslsp(capsys, "experiment", "house-roof", "--faults")
    assert code == 2 and "--faults applies to the VSL-SP experiments" in err
    with pytest.raises(InputError, match="--planner applies to the VSL-SP experiments"):
        get_task("house-roof", planner="fast-downward")
