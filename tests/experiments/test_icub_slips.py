"""The tutor's slips on the iCub (issue 30, item 1): a demonstrated operation that also nudges
another cube, on rendered scenes; the detection finds every moved cube and names the operated one,
learning keeps a disturbed cube as it was before its slip, and the trials succeed."""

from __future__ import annotations

import numpy as np
import pytest

from vslsp.errors import GroundingFailed
from vslsp.experiments.icub_slips import Watcher
from vslsp.grounding.operation import ground
from vslsp.loop.perception import perceive
from vslsp.sim import CubeSpec, LandmarkSpec, LineWorld, SceneSpec
from vslsp.symbolic import learn_task
from vslsp.tasks import get_task
from vslsp.vsl.slips.colour import draw_moves, ground_moves
from vslsp.worlds.icub import SLIP_CLEARANCE, tutor_operation, tutor_slip
from vslsp.worlds.slips import Slip

LINE = LandmarkSpec(x=0.225, angle=0.1)


def _scene(*cubes: tuple[str, float, float]) -> SceneSpec:
    """Cubes (colour, along, across) placed in metres along and across :data:`LINE`."""
    specs = []
    for colour, along, across in cubes:
        x, y = LINE.point + along * LINE.direction + across * LINE.normal
        specs.append(CubeSpec(colour, colour, float(x), float(y), 0.1))
    return SceneSpec(tuple(specs), LINE)


def _nudge(name: str, along: float, across: float, turn: float = 10.0) -> Slip:
    dx, dy = along * LINE.direction + across * LINE.normal
    return Slip(1, name, float(dx), float(dy), turn)


def test_detection_finds_both_moved_cubes_and_names_the_operated_one():
    spec = _scene(("orange", 0.10, 0.06), ("green", 0.0, -0.05), ("blue", -0.10, 0.07))
    with LineWorld(spec, robot=False) as world:
        pre = world.observe("head").rgb
        tutor_operation(world, "orange", "pull")
        applied = tutor_slip(world, _nudge("green", 0.0, -0.03, 15.0))  # a nudge that keeps its side
        post = world.observe("head").rgb
    assert applied is not None
    moves = ground_moves(pre, post)
    assert sorted(g.name for g in moves.moved) == ["green", "orange"]
    assert moves.operated.name == "orange" and moves.operated.action == "pull"
    assert [g.name for g in moves.disturbed] == ["green"] and not moves.crossed
    assert moves.to_dict()["disturbed"] == ["green"]
    # The picture boxes the disturbed cube in cyan in both panels (and the operated one as ever).
    picture = draw_moves(pre, post, moves)
    assert picture.shape == (pre.shape[0], 2 * pre.shape[1], 3)
    green = moves.disturbed[0]
    for offset, obj in ((0, green.pre_object), (pre.shape[1], green.post_object)):
        x, y, w, h = obj.box
        edge = picture[y : y + h + 1, x + offset : x + offset + 2]  # the box's left side
        assert np.any(np.all(edge == (0, 255, 255), axis=-1))
    # The paper's VSL (the detection off) takes one moved object per operation and gives up.
    with pytest.raises(GroundingFailed, match="more than one object moved"):
        ground(pre, post)


def test_a_cube_slipped_across_the_line_is_learned_as_before_its_slip():
    # pull-in-order's demonstration, all far; in the first operation the tutor's hand pulls
    # yellow (2.5 cm beyond the line) 4 cm across it. Its later pull then changes no side in the
    # images, but it is what the tutor meant: the learner keeps yellow far until that pull.
    spec = _scene(("orange", 0.10, 0.06), ("green", 0.0, 0.05), ("yellow", -0.10, 0.025))
    watcher = Watcher(seed=0)
    steps = []
    with LineWorld(spec, robot=False) as world:
        state = perceive(world)
        for k, colour in enumerate(("orange", "green", "yellow")):
            tutor_operation(world, colour, "pull")
            if k == 0:
                assert tutor_slip(world, _nudge("yellow", 0.0, -0.04)) is not None
                assert not world.is_far("yellow")  # truth: the slip put it across the line
            after = perceive(world)
            grounding, moves = watcher.ground("demonstration", state.image, after.image)
            assert moves is not None and grounding.name == colour
            watcher.record("demonstration", k + 1, f"pull {colour}", grounding, moves, None)
            steps.append(watcher.step(grounding, moves, state, after, ()))
            state = after
    first = watcher.records[0]
    assert first["moved"] == ["orange", "yellow"] and first["operated"] == "orange"
    assert first["far"]["yellow"] == {"pre": True, "post": False}
    assert "yellow was disturbed across the line" in watcher.notes[0] and "not part of the goal" in watcher.notes[0]
    assert steps[0].after["yellow"]["far"] is True  # kept as before the slip
    assert [s.action for s in steps] == ["pull", "pull", "pull"]
    task = learn_task([steps], ordered=True)
    assert task.goal.to_pddl() == "(and (not (far orange)) (not (far green)) (not (far yellow)))"
    assert len(task.constraints) == 2  # orange before green before yellow, as demonstrated


def test_a_nudge_towards_another_cubes_lane_goes_the_other_way_or_not_at_all():
    with LineWorld(_scene(("orange", 0.08, 0.06), ("green", -0.02, -0.05)), robot=False) as world:
        start = np.array(world.cube_pose("green")[:2])
        # 4 cm along towards orange would leave 6 cm between their lanes: it goes the other way.
        applied = tutor_slip(world, _nudge("green", 0.04, -0.01))
        assert applied is not None
        shift = np.array([applied.dx_m, applied.dy_m])
        assert shift @ LINE.direction == pytest.approx(-0.04, abs=1e-6)
        assert shift @ LINE.normal == pytest.approx(-0.01, abs=1e-6)
        assert np.allclose(world.cube_pose("green")[:2], start + shift, atol=0.003)
        lane = (np.array(world.cube_pose("orange")[:2]) - np.array(world.cube_pose("green")[:2])) @ LINE.direction
        assert abs(lane) >= SLIP_CLEARANCE
    # Between two cubes 8 cm away on either side, 2 cm either way is too close: the hand misses.
    with LineWorld(
        _scene(("orange", 0.06, 0.06), ("green", -0.02, -0.05), ("blue", -0.10, 0.06)), robot=False
    ) as world:
        start = np.array(world.cube_pose("green")[:2])
        assert tutor_slip(world, _nudge("green", 0.02, 0.0)) is None
        assert np.allclose(world.cube_pose("green")[:2], start)


@pytest.mark.slow
def test_pull_in_order_succeeds_when_the_tutor_slips_in_every_operation(library, tmp_path):
    task = get_task("pull-in-order", tutor_slips=1.0)
    result = task.run_trial(3, keep=True)
    assert result.success, result.error
    operations = result.details["tutor_operations"]
    assert len(operations) == 3
    for op in operations:
        assert op["slip"]["applied"] and op["operated"] == op["tutor"].split()[1]
        assert op["disturbed"] == [op["slip"]["object"]] and len(op["moved"]) == 2
    assert result.details["vsl_order"] == result.details["vsl_sp_order"] == ["orange", "green", "yellow"]
    figures = task.figures(tmp_path, result)
    shown = [image for image in figures["images"] if image["title"].startswith("demonstration")]
    assert [image["disturbed"] for image in shown] == [op["disturbed"] for op in operations]
    assert all("disturbed:" in image["caption"] for image in shown)
    # The same trial with the detection off (the paper's VSL) fails at the first slip.
    off = get_task("pull-in-order", tutor_slips=1.0, slip_detection=False).run_trial(3)
    assert not off.success and "more than one object moved" in (off.error or "")
    assert "error" in off.details["tutor_operations"][0]


@pytest.mark.slow
def test_no_slip_gives_the_trial_without_the_option(library):
    plain = get_task("simple-vsl-task").run_trial(4).to_dict()
    slips = get_task("simple-vsl-task", tutor_slips=0.0).run_trial(4).to_dict()
    assert [op.get("slip") for op in slips.pop("tutor_operations")] == [None, None, None]
    assert slips.pop("disturbances") == []
    for record in (plain, slips):
        for key in ("time_s", "cpu_s", "stages_s"):
            record.pop(key, None)
    assert slips == plain


@pytest.mark.slow
def test_a_cube_disturbed_in_one_demonstration_is_learned_afresh_in_the_next(library):
    # Seed 42: yellow is nudged in demonstration 1 and pulled by the tutor in demonstration 2, a
    # new scene. What the learner held of yellow from demonstration 1 is no part of it (it once
    # hid the pull, so only blue's rule was learned and the goal named blue alone).
    result = get_task("keep-all-near", tutor_slips=0.5).run_trial(42)
    assert result.success, result.error
    assert result.details["tutor_operations"][0]["disturbed"] == ["yellow"]
    assert result.details["tutor_operations"][1]["tutor"] == "pull yellow"
    assert result.details["learned"]["goal"] == "(forall (?b - block) (not (far ?b)))"
