"""Hard cases of VSL-3D found in the seeded experiments, each on its real rendered scene: a
near-symmetric flip of a partly hidden object in getObject, a view of the placed object that
shares only a third of the recorded one, a landmark box the features match onto the other box,
a box matched tipped over with an edge sunk into the table, and point-to-plane ICP sliding a flat
box off its place."""

import json
from pathlib import Path

import numpy as np
import pytest

from vslsp.experiments import stacking, table_cleaning
from vslsp.experiments.cloud_reproduction import world_of
from vslsp.sim.cloud_scene import BOXES
from vslsp.vsl3d.matching import CloudMatch, find_best_match
from vslsp.vsl3d.registration import transform_error
from vslsp.vsl3d.vsl import get_object
from vslsp.worlds.rgbd_table import RgbdTable

TOLERANCE_M, TOLERANCE_DEG = 0.01, 5.0
# The seeds' scenes as they were drawn when each case failed (the layouts drawn now keep every
# stack in the sensor's view, which moved some of these scenes).
SCENES = json.loads((Path(__file__).parent / "data" / "hard_layouts.json").read_text())


def _scenes(experiment: str, seed: int) -> tuple[dict, dict]:
    """The demonstration's and the moved scene's layouts (name -> (x, y, yaw)) of ``seed``."""
    before, after = SCENES[experiment][str(seed)]
    return {k: tuple(v) for k, v in before.items()}, {k: tuple(v) for k, v in after.items()}


@pytest.mark.parametrize(("seed", "name"), [(3, "teddy"), (30, "duckling")])
def test_get_object_tells_the_true_turn_from_a_near_symmetric_flip(seed, name):
    """Seed 3: the teddy put in the tray, partly hidden by its rim, fitted as well turned by
    177 deg; seed 30: the duckling's recorded motion was 140 deg off. Both flips put points
    where one of the two captures saw free space."""
    rng = np.random.default_rng(seed)
    layout, _ = _scenes("table-cleaning", seed)
    with RgbdTable(layout, robot=True) as scene:
        before = scene.pose(name)
        centre = sum(scene.bounds(name)) / 2.0
        demonstrated, goals, _ = table_cleaning.demonstrate(scene, layout, rng, "prerejective_ransac", seed)
    moved, failure = demonstrated[[n for n, _, _ in table_cleaning.OPERATIONS].index(name)]
    assert moved is not None, failure
    offset, angle = transform_error(moved.transform, goals[name] @ np.linalg.inv(before), centre)
    assert offset < TOLERANCE_M and angle < TOLERANCE_DEG


def _stacking_demonstration(seed: int):
    """The stacking demonstration of ``seed`` as the experiment runs it, then the first capture of
    the moved scene: per operation getObject's result and the true motion, the landmarks, and
    the new world with the boxes' true motions (one per symmetric turn)."""
    rng = np.random.default_rng(seed)
    layout, new = _scenes("stacking", seed)
    objects = {name: layout[name] for name, _ in stacking.OPERATIONS}
    demonstrated, boxes_before = [], {}
    with RgbdTable(objects, tray=False, robot=True, boxes={box: layout[box] for box in BOXES}) as scene:
        for name, box in stacking.OPERATIONS:
            scene.park()
            pre_image, before = scene.capture(), scene.pose(name)
            centre = sum(scene.bounds(name)) / 2.0
            x, y = scene.pose(box)[:2, 3]
            yaw = layout[name][2] + rng.uniform(-stacking.MAX_TURN, stacking.MAX_TURN)
            scene.tutor_move(name, scene.resting_pose(name, x, y, yaw, support=BOXES[box][2]))
            scene.settle()
            pre = world_of(pre_image)
            moved = get_object(pre, world_of(scene.capture()), seed=seed)
            truth = scene.pose(name) @ np.linalg.inv(before)
            demonstrated.append((moved, truth, centre, stacking.landmark_under(pre, moved)))
            boxes_before[box] = scene.pose(box)
    objects = {
        name: (*new[name][:2], layout[name][2] + rng.uniform(-stacking.MAX_TURN, stacking.MAX_TURN))
        for name, _ in stacking.OPERATIONS
    }
    with RgbdTable(objects, tray=False, robot=True, boxes={box: new[box] for box in BOXES}) as scene:
        scene.park()
        world = world_of(scene.capture())
        motions = {}
        for box, symmetry in stacking.BOX_SYMMETRY.items():
            motions[box] = []
            for k in range(symmetry):
                turn = np.eye(4)
                c, s = np.cos(2.0 * np.pi * k / symmetry), np.sin(2.0 * np.pi * k / symmetry)
                turn[:2, :2] = [[c, -s], [s, c]]
                motions[box].append(scene.pose(box) @ turn @ np.linalg.inv(boxes_before[box]))
    return demonstrated, world, motions


@pytest.mark.parametrize(
    ("seed", "box"), [(5, "box1"), (8, "box2"), (52, "box1"), (81, "box1"), (46, "box2"), (63, "box2")]
)
def test_stacking_demonstration_and_landmarks(seed, box):
    """Seed 8: the teddy put on box2 at the image's edge, turned, shows a third of the recorded
    view (getObject counts the fit against what the post capture could see); its box2 in the
    moved scene matched tipped over (an edge sunk into the table). Seed 5: box1, partly hidden
    behind box2, was matched onto box2 (its points in free space) and not found. Seed 52: box1's
    global match, its top face on box2, fitted 63 % without floating (the windows are searched
    below 75 %). Seed 81: point-to-plane ICP slid box1 off its window from every start (point
    pairs are tried when a refined pose fits less than half). Seeds 46 and 63: the near-cubic
    box2 fitted tipped on its side (87 %) better than upright (84 %), whose rim a pose 2 mm off
    put beside the box's silhouette, where the sensor saw the table behind (free space is now
    what the sensor saw through all around a pixel, and a tipped pose of a resting box scores
    less)."""
    demonstrated, world, motions = _stacking_demonstration(seed)
    for moved, truth, centre, _ in demonstrated:
        offset, angle = transform_error(moved.transform, truth, centre)
        assert offset < TOLERANCE_M and angle < TOLERANCE_DEG
    landmark = demonstrated[[b for _, b in stacking.OPERATIONS].index(box)][3]
    match = find_best_match(world, landmark, seed=seed)
    assert isinstance(match, CloudMatch), match
    centre = landmark.points.mean(axis=0)
    offset, angle = min(
        (transform_error(match.registration.transform, motion, centre) for motion in motions[box]),
        key=lambda error: error[1],
    )
    assert offset < TOLERANCE_M and angle < TOLERANCE_DEG


@pytest.mark.slow
@pytest.mark.parametrize(("experiment", "seed"), [("stacking", 27), ("stacking", 60), ("table-cleaning", 62)])
def test_whole_trials_that_once_failed(experiment, seed):
    """Whole trials, executed by the robot. Stacking 27: the teddy, turned 60 deg from its
    recorded view, fitted its landmark box's corner (59 %) and its own flip (64 %, tipped 52 deg)
    better than itself (57 %); a landmark is no candidate for an object, and a tipped pose pays
    for its tilt. Stacking 60: box1 matched upside down (89 %). Table cleaning 62: the duckling's
    view fitted the teddy already put in the box; what the robot has put down is no candidate."""
    if experiment == "stacking":
        operations, _ = stacking.run_stacking(seed)
    else:
        operations = table_cleaning.run_table_cleaning(seed)[0].operations
    for operation in operations:
        assert operation.success, operation.to_dict()
