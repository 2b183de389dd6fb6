"""tower-of-hanoi (paper, "Tower of Hanoi"): seven moves, several on one disk, stacking; the
user's intervention moves the tower to the third base; ground truth."""

import pytest

from vslsp.worlds.panda_table import layouts as scenes

pytestmark = pytest.mark.slow


def test_tower_of_hanoi_with_the_users_intervention_ends_on_the_third_base(reproduce):
    outcomes, poses, _ = reproduce("tower-of-hanoi", 1)  # odd seed: the user intervenes
    assert [o.actor for o in outcomes] == ["tutor"] + ["robot"] * 6  # the tutor made move 1, the robot 2-7
    base = poses["base-3"]
    bottoms = [scenes.BASE[2] + sum(scenes.DISKS[j][2] for j in range(k + 1, 4)) for k in (1, 2, 3)]
    for k, bottom in zip((1, 2, 3), bottoms):
        # each disk goes where it was on the one below: offsets add up the tower (see the report)
        assert poses[f"disk-{k}"][:2] == pytest.approx(base[:2], abs=0.03)
        assert poses[f"disk-{k}"][2] == pytest.approx(bottom, abs=0.004)  # stacked large, medium, small
