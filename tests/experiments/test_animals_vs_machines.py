"""animals-vs-machines (paper, "Animals vs. Machines"): cards presented one at a time in a new
order, each found in the pre-pick dictionary and put in its class's bin; ground truth."""

import pytest

from vslsp.worlds.panda_table import layouts as scenes

pytestmark = pytest.mark.slow


def test_animals_vs_machines_sorts_cards_presented_in_a_new_order_into_their_bins(reproduce, local):
    outcomes, poses, _ = reproduce("animals-vs-machines", 0)
    demo_order = [o.item for o in outcomes]
    assert sorted(demo_order) == sorted(scenes.SUBJECTS)
    for subject, kind in scenes.textures.PICTURES.items():
        x, y, _ = local(poses, f"bin-{kind}s", subject)
        assert abs(x) < scenes.BIN[0] / 2 and abs(y) < scenes.BIN[1] / 2  # inside its bin
