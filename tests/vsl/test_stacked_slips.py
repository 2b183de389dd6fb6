"""The slip detection (vslsp.vsl.slips) on rendered Tower-of-Hanoi stacks on the Panda table: a
disk that the operated one covered, then nudged, is found (only the pre-place observation shows
it whole); a disk put on a stack is the operation, not the disk below it moved; a disk put on
a nudged one is placed by that disk (its own pre-place frame)."""

from __future__ import annotations

import numpy as np
import pytest

from vslsp.experiments.tabletop_protocol import look
from vslsp.vsl.pick_place import TableView
from vslsp.vsl.slips.restore import separate
from vslsp.worlds.panda_table import PandaTable, Placement
from vslsp.worlds.panda_table import layouts as scenes
from vslsp.worlds.slips import Slip


def stack(*piles: tuple[int, list[int]]) -> list:
    """Bases 1-3 and, per (base, disks bottom first), the disks stacked on it."""
    disks = {int(d.name.split("-")[1]): d for d in scenes.hanoi_disks()}
    layout = scenes.hanoi_bases()
    for base, numbers in piles:
        x, y, _ = scenes.BASE_POSES[base]
        below = f"base-{base}"
        for number in numbers:
            layout.append((disks[number], Placement(x, y, 0.0, on=below)))
            below = f"disk-{number}"
    return layout


def pixel(world: PandaTable, name: str) -> tuple[float, float]:
    x, y, z, _ = world.truth(name)
    return TableView(world).table_to_pixel(x, y, z + world.specs[name].size[2])


def near(point, target, reach: float = 40.0) -> bool:
    return float(np.hypot(point[0] - target[0], point[1] - target[1])) <= reach


def operate(world: PandaTable, name: str, where: Placement, slip: Slip | None):
    """The tutor takes ``name``, puts it at ``where``, and the hand may ``slip``: the pre,
    pre-place and post observations."""
    pre = look(world)
    world.tutor_move(name, scenes.hold_placement(0))
    pre_place = look(world)
    world.tutor_move(name, where)
    if slip is not None:
        assert world.nudge(slip) is not None
    return pre, pre_place, look(world)


def test_a_disk_uncovered_by_the_operation_then_nudged_is_disturbed():
    # Disk 1 lies on disk 2, which hides all but a sliver of disk 2 in the pre observation.
    with PandaTable.from_layout(stack((1, []), (3, [2, 1])), seed=0) as world:
        before = pixel(world, "disk-2")
        x, y, _ = scenes.BASE_POSES[1]
        pre, pre_place, post = operate(
            world, "disk-1", Placement(x, y, 0.0, on="base-1"), Slip(0, "disk-2", 0.012, 0.008, 15.0)
        )
        moves, meant = separate(pre, post, pre_place)
        assert moves.operated is not None and near(moves.operated.after, pixel(world, "disk-1"))
        (disturbed,) = moves.disturbed
        assert near(disturbed.before, before) and near(disturbed.after, pixel(world, "disk-2"), 25.0)
        # the disturbed disk is restored from the pre-place observation (disk 1 already taken
        # from it), not from the pre one (which would put disk 1 back on it)
        u, v = (int(round(c)) for c in before)
        assert np.array_equal(meant[v, u], pre_place[v, u])


@pytest.mark.slow
def test_a_disk_put_on_a_stack_is_the_operation_and_nothing_else_moved():
    """Tower of Hanoi seed 500 at P = 0.5. Operation 5: disk 1 is lifted off disk 2, which the
    hand then nudges (found in the pre-place observation). Operation 7: disk 1 is put on disk 2
    (on disk 3); a short fit of disk 2's top onto disk 1 arriving over it took disk 1's place
    in the nearest-first pairing, so disk 1 is paired first: it is the operation, and nothing
    else moved."""
    from vslsp.tasks import get_task

    result = get_task("tower-of-hanoi", tutor_slips=0.5, slip_detection=True).run_trial(500)
    assert result.success, result.error
    fifth, seventh = result.operations[4], result.operations[6]
    assert fifth["slip"]["object"] == "disk-2" and fifth["disturbed"] == ["disk-2"]
    assert fifth["operated"] == "disk-1"
    assert "slip" not in seventh and seventh["operated"] == "disk-1" and seventh["disturbed"] == []


@pytest.mark.slow
def test_identical_roofs_a_nudge_and_a_carry_pair_nearest_first():
    """house-roof seed 53 at P = 0.5, operation 2: a roof is put on a body (turned, its arrival
    shows few features) while the hand nudges an identical roof. The nudge fits its roof well
    (it leaves 5 % of the difference), the carry onto the arrival better (2 %): a fit that
    explains its object that well does not wait for a rival, so the nudge is the slip."""
    from vslsp.tasks import get_task

    result = get_task("house-roof", tutor_slips=0.5, slip_detection=True).run_trial(53)
    assert result.success, result.error
    second = result.operations[1]
    assert second["slip"]["object"] == "roof-2" and second["disturbed"] == ["roof-2"]
    assert second["operated"] == "roof-1"


@pytest.mark.slow
@pytest.mark.parametrize("seed", [1, 77])
def test_a_disk_put_on_a_nudged_disk_is_placed_by_it(seed):
    """Tower of Hanoi at P = 0.5: the fifth move's slip nudges disk 3 off its base's centre (4
    cm on seed 1, 1.3 cm on seed 77, after a first slip of 2.2 cm), the tutor stacks disk 2 and
    then disk 1 on it where it lies; the new world has disk 3 centred. Those two places are
    found by the disk below (its features matched as the pick matches its object; reported
    with a frame of its size), and the trial succeeds."""
    from vslsp.tasks import get_task

    result = get_task("tower-of-hanoi", tutor_slips=0.5, slip_detection=True).run_trial(seed)
    assert result.success, result.error
    fifth, sixth, seventh = result.operations[4:7]
    assert fifth["slip"]["object"] == "disk-3" and fifth["disturbed"] == ["disk-3"]
    for op in (sixth, seventh):
        assert op["plan"]["place_match"]["frame"] < 200  # the disk's size, not 2x the biggest object
        assert not op["plan"]["place_match"]["ambiguous"]


def test_the_tutor_stacks_on_a_nudged_disk_where_it_lies():
    with PandaTable.from_layout(stack((1, [2]), (2, [3])), seed=0) as world:
        x, y, _ = scenes.BASE_POSES[2]
        meant = Placement(x, y, 0.0, on="disk-3")
        assert world.as_it_lies(meant) == meant  # no slip: as meant
        applied = world.nudge(Slip(0, "disk-3", 0.02, -0.01, 5.0))
        assert applied is not None
        on_nudged = world.as_it_lies(meant)
        assert (on_nudged.x - x, on_nudged.y - y) == pytest.approx((applied.dx_m, applied.dy_m))
        world.tutor_move("disk-2", on_nudged)
        assert world.truth("disk-2")[:2] == pytest.approx(world.truth("disk-3")[:2], abs=0.004)
        # what goes on disk 2 follows disk 3's slip too; a base was never nudged
        on_top = world.as_it_lies(Placement(x, y, 0.0, on="disk-2"))
        assert (on_top.x, on_top.y) == (on_nudged.x, on_nudged.y)
        assert world.as_it_lies(Placement(x, y, 0.0, on="base-1")).x == x


@pytest.mark.slow
def test_a_nudge_seen_after_the_taking_is_not_swallowed_by_a_fit_of_identical_bases():
    """Tower of Hanoi seed 30 at P = 0.5, operation 5: disk 1 is lifted off disk 2 and put on
    base 1, and the hand nudges disk 2. Between the pre-place and post observations the nudge
    fits, and so does base 1's look onto base 3's (disk 1 covered the one, the nudge uncovered
    the other); every nudge found there is a slip, whatever else fits."""
    from vslsp.tasks import get_task

    result = get_task("tower-of-hanoi", tutor_slips=0.5, slip_detection=True).run_trial(30)
    assert result.success, result.error
    fifth = result.operations[4]
    assert fifth["slip"]["object"] == "disk-2" and fifth["disturbed"] == ["disk-2"]


@pytest.mark.slow
@pytest.mark.parametrize(
    ("seed", "operation", "nudged"),
    [
        # the piece a slip had pushed out of line, put at the row's end beside where it was
        (21, 5, None),
        # the operated piece not identified (dominoes look alike in part); its arrival shares a
        # changed region with the nudged piece, which alone is restored
        (37, 2, "domino-1"),
        # the nudged piece turned against its neighbour and pushed it a little; the operated
        # piece's arrival, widened by that shift, is recorded from its own pixels alone
        (62, 5, "domino-3"),
    ],
)
def test_dominoes_a_short_carry_is_the_operation_and_an_unidentified_arrival_is_kept(seed, operation, nudged):
    from vslsp.tasks import get_task

    result = get_task("domino", tutor_slips=0.5, slip_detection=True).run_trial(seed)
    assert result.success, result.error
    record = next(op for op in result.operations if op["operation"] == operation and "operated" in op)
    assert record["disturbed"] == ([nudged] if nudged else [])


@pytest.mark.slow
def test_the_taken_roof_is_not_paired_onto_a_nudged_roofs_new_place():
    """house-roof seed 80 at P = 0.5, operation 2: a roof goes onto a body while the hand nudges
    an identical roof. The taken roof's own arrival shows too few features to fit; paired first,
    it fits onto the nudged roof's new place, which a nudge seen between the pre-place and post
    observations explains: the nudge is the slip, and the arrival is left to the recorder."""
    from vslsp.tasks import get_task

    result = get_task("house-roof", tutor_slips=0.5, slip_detection=True).run_trial(80)
    assert result.success, result.error
    second = result.operations[1]
    assert second["slip"]["object"] == "roof-2" and second["disturbed"] == ["roof-2"]
