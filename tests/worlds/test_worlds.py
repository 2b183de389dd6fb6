"""Each of the paper's four worlds is a :class:`vslsp.worlds.World`: built from a seeded layout,
observed by its sensor, changed by the tutor (the truth follows), and the same for the same
layout."""

import numpy as np
import pytest

from vslsp.sim import Observation
from vslsp.sim.cloud_scene import RGBDImage
from vslsp.worlds import World
from vslsp.worlds.house_roof import HouseBoard, HouseWorld, roof_name
from vslsp.worlds.icub import IcubLineWorld, line_layout
from vslsp.worlds.panda_table import PandaTable, Placement
from vslsp.worlds.panda_table import layouts as scenes
from vslsp.worlds.rgbd_table import RgbdTable, random_layout


def test_the_house_board_observes_its_truth_and_the_tutor_moves_a_roof():
    board = HouseBoard.from_layout(HouseWorld.random(3))
    assert isinstance(board, World) and board.robot is None
    before = board.observe()
    assert before.shape == (720, 960, 3) and np.array_equal(before, HouseWorld.random(3).render())
    board.tutor_move(roof_name(1), None)  # lifted: out of view
    assert board.truth(roof_name(1)) is None and not np.array_equal(board.observe(), before)
    board.tutor_move(roof_name(1), (480.0, 300.0, 0.5))
    assert board.truth(roof_name(1)) == (480.0, 300.0, 0.5)


def test_the_panda_table_is_a_world_whose_tutor_moves_the_truth():
    layout = scenes.baseline_arms() + [(scenes.letters()[0], Placement(0.42, 0.1, 0.2))]
    with PandaTable.from_layout(layout, seed=1) as world:
        assert isinstance(world, World) and world.robot is world.panda
        image = world.observe()
        assert image.ndim == 3 and image.dtype == np.uint8
        world.tutor_move("A", Placement(0.5, -0.1, 0.4))
        x, y, _, yaw = world.truth("A")
        assert (x, y, yaw) == pytest.approx((0.5, -0.1, 0.4), abs=2e-3)


@pytest.mark.slow
def test_the_icub_line_world_is_a_world_built_from_its_seeded_layout():
    layout = line_layout(4, ("red", "green"))
    assert layout == line_layout(4, ("red", "green"))
    with IcubLineWorld.from_layout(layout) as world:
        assert isinstance(world, World) and world.robot is not None
        assert isinstance(world.observe(), Observation)
        cube = layout.cubes[0].name
        world.tutor_move(cube, (0.3, 0.05))
        assert world.truth(cube)[:2] == pytest.approx((0.3, 0.05), abs=0.01)


@pytest.mark.slow
def test_the_rgbd_table_is_a_world_seen_as_rgbd_images():
    layout = random_layout(["duck", "mug"], 2)
    assert layout == random_layout(["duck", "mug"], 2)
    with RgbdTable.from_layout(layout) as world:
        assert isinstance(world, World) and world.robot is world.panda is not None
        assert isinstance(world.observe(), RGBDImage)
        goal = world.truth("duck").copy()
        goal[:2, 3] += (0.05, 0.02)
        world.tutor_move("duck", goal)
        assert world.truth("duck")[:2, 3] == pytest.approx(goal[:2, 3], abs=1e-3)
