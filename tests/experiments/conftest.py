"""Shared by the tabletop task tests: a task demonstrated and reproduced, with the ground truth."""

import numpy as np
import pytest

from vslsp.experiments.seeds import reproduction_seed
from vslsp.tasks import get_task
from vslsp.worlds.panda_table import PandaTable
from vslsp.worlds.panda_table import layouts as scenes


@pytest.fixture
def reproduce():
    """``reproduce(name, seed)``: the tutor demonstrates task ``name``, the Panda reproduces it in
    a new random world; asserts the goal and that every robot operation succeeded, and returns
    the outcomes, the final poses of every item and the demonstration's landmark poses (ground
    truth, read here only)."""

    def run(name: str, seed: int):
        task = get_task(name).for_seed(seed)
        rng = np.random.default_rng(seed)
        with PandaTable.from_layout(task.layout(rng, "demonstration"), seed) as world:
            demo = task.demonstrate(world, rng)
            landmarks = {n: world.pose(n) for n, item in world.specs.items() if not item.movable}
        rng = np.random.default_rng(reproduction_seed(seed))
        with PandaTable.from_layout(task.layout(rng, "reproduction"), seed) as world:
            outcomes = task.reproduce(world, demo, rng)
            poses = {n: world.pose(n) for n in world.items()}
            reached = task.goal(world, demo, outcomes)
        robot = [o for o in outcomes if o.actor == "robot"]
        assert robot and all(o.diagnosis == "ok" for o in robot), [o.to_dict() for o in outcomes]
        assert reached
        return outcomes, poses, landmarks

    return run


@pytest.fixture
def local():
    """``local(poses, frame, item)``: ``item``'s pose (x, y, yaw) seen from ``frame``, from the
    ground-truth poses (x, y, z, yaw) that ``reproduce`` returns."""

    def seen_from(poses: dict, frame: str, item: str) -> tuple[float, float, float]:
        x, y, _, yaw = poses[frame]
        return scenes.relative((x, y, yaw), (poses[item][0], poses[item][1], poses[item][3]))

    return seen_from
