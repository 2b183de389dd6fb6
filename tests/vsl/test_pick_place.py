"""VSL's pick-and-place perception in the tabletop world: the top-down view, the recorder
(pick point, footprint, yaw and turn from image subtraction and SIFT), the plan in a new world
(pick and place poses from the matched transforms), and the dictionary searches. Checked
against the simulator's ground truth, which perception never reads."""

import numpy as np
import pytest

from vslsp.errors import InputError
from vslsp.geometry.poses import wrap
from vslsp.sim.tabletop import Placement, TabletopWorld
from vslsp.vision.features import Features, extract_features
from vslsp.vsl.pick_place import TableModel, TableView, apply, changed_region, object_candidates
from vslsp.vsl.recorder import Heights, Recorder
from vslsp.vsl.reproduction import correction, identify, identify_moved, plan_operation
from vslsp.worlds.panda_table import layouts as scenes

LETTERS = {item.name: item for item in scenes.letters()}
FROM, TO = Placement(0.42, 0.12, 0.4), Placement(0.64, 0.07, 1.9)  # the tutor turns A by 1.5 rad


def world_with(a: Placement, b: Placement = Placement(0.40, -0.15, -0.7)) -> TabletopWorld:
    return TabletopWorld(scenes.baseline_arms() + [(LETTERS["A"], a), (LETTERS["B"], b)])


def look(world: TabletopWorld) -> np.ndarray:
    return TableView(world).rectify(world.observe())


@pytest.fixture(scope="module")
def recorded():
    """The tutor moves A from FROM to TO; the recorder records it."""
    with world_with(FROM) as world:
        recorder = Recorder(TableModel(TableView(world)))
        pre_pick = look(world)
        world.tutor_place("A", scenes.hold_placement(0))
        pre_place = look(world)
        world.tutor_place("A", TO)
        height = LETTERS["A"].size[2]
        recorder.record(pre_pick, look(world), pre_place, Heights(height, height, height))
        return recorder.demonstration(), world.pose("A")


def test_the_top_down_view_maps_pixels_and_table_points_both_ways():
    with world_with(FROM) as world:
        view = TableView(world)
        for x, y, z in ((0.3, -0.3, 0.0), (0.5, 0.1, 0.03), (0.7, 0.25, 0.08)):
            assert view.pixel_to_table(*view.table_to_pixel(x, y, z), z) == pytest.approx((x, y), abs=1e-6)
        image = view.rectify(world.observe())
    assert image.shape == (view.size[1], view.size[0], 3)


def test_the_recorder_finds_the_object_its_footprint_and_the_turn(recorded):
    demo, after = recorded
    (op,) = demo.operations
    view_of = TableView(_Camera())
    assert view_of.pixel_to_table(*op.pick_point, op.pick_z) == pytest.approx((FROM.x, FROM.y), abs=0.004)
    assert view_of.pixel_to_table(*op.place_point, op.place_z) == pytest.approx(after[:2], abs=0.004)
    assert sorted(op.footprint) == pytest.approx(sorted(LETTERS["A"].size[:2]), abs=0.005)
    assert abs(wrap(op.turn - (after[3] - FROM.yaw))) < np.radians(3.0)
    # the yaw of the box (modulo a quarter turn: it is a box seen from above)
    assert abs(wrap(4 * (op.yaw - FROM.yaw))) / 4 < np.radians(3.0)
    assert len(op.features) >= 20


class _Camera:
    """The tabletop camera without a world (its calibration only)."""

    def __init__(self):
        from vslsp.sim.tabletop import tabletop_camera

        self.camera = tabletop_camera()

    def pixel_to_table(self, u, v, z=0.0):
        return self.camera.pixel_to_table(u, v, z)

    def table_to_pixel(self, x, y, z=0.0):
        return self.camera.table_to_pixel(x, y, z)


def test_the_plan_in_a_new_world_picks_the_object_where_it_is_and_places_it_as_demonstrated(recorded):
    demo, after = recorded
    elsewhere = Placement(0.36, -0.02, -2.5)
    with world_with(elsewhere, Placement(0.45, 0.2, 1.0)) as world:
        image = look(world)
        plan = plan_operation(demo, 0, image, TableView(world), extract_features(image))
    assert plan.pick[:2] == pytest.approx((elsewhere.x, elsewhere.y), abs=0.005)
    assert plan.place[:2] == pytest.approx(after[:2], abs=0.005)
    # the hand turns the object from its yaw now to the demonstrated yaw at the place
    assert abs(wrap(plan.place[2] - plan.pick[2] - (after[3] - elsewhere.yaw))) < np.radians(4.0)
    # it closes across the narrow side, on the branch that turns the wrist least
    assert plan.grasp_width == pytest.approx(LETTERS["A"].size[0], abs=0.005)
    assert abs(wrap(2 * (plan.pick[2] - elsewhere.yaw))) < np.radians(8.0)
    assert max(abs(plan.pick[2]), abs(plan.place[2])) <= np.pi + 1e-9
    assert not plan.pick_match.ambiguous


def test_the_last_look_puts_right_an_object_left_off_its_place_and_leaves_one_on_it(recorded):
    demo, after = recorded
    with world_with(Placement(0.36, -0.02, -2.5), Placement(0.45, 0.2, 1.0)) as world:
        image = look(world)
        plan = plan_operation(demo, 0, image, TableView(world), extract_features(image))
        world.tutor_place("A", Placement(plan.place[0], plan.place[1], after[3]))  # as planned
        assert correction(demo, 0, look(world), TableView(world), plan) is None
        off = Placement(plan.place[0] + 0.02, plan.place[1] - 0.015, after[3] + 0.2)  # nudged 2.5 cm, turned
        world.tutor_place("A", off)
        fix = correction(demo, 0, look(world), TableView(world), plan)
        assert fix is not None and fix.pick[:2] == pytest.approx((off.x, off.y), abs=0.005)
        assert fix.place[:2] == pytest.approx(plan.place[:2], abs=1e-9)
        assert world.pick_and_place(fix.pick, fix.place, fix.grasp_width).ok
        x, y, _, yaw = world.pose("A")
    assert (x, y) == pytest.approx(after[:2], abs=0.006)
    assert abs(wrap(yaw - after[3])) < np.radians(4.0)


def test_a_placement_that_maps_many_features_onto_one_spot_loses_to_the_object_seen_turned():
    rng = np.random.default_rng(3)
    points = rng.uniform(0, 100, (40, 2)).astype(np.float32)
    obj = Features(
        np.column_stack([points, np.full((40, 2), 3.0, np.float32)]), rng.uniform(0, 1, (40, 128)).astype(np.float32)
    )
    turn = np.radians(160.0)
    rotation = np.array([[np.cos(turn), -np.sin(turn)], [np.sin(turn), np.cos(turn)]])
    turned = points[:8] @ rotation.T + (600.0, 400.0)  # the object, 8 features found again
    spot = np.full((12, 2), (200.0, 150.0)) + rng.uniform(-1, 1, (12, 2))  # 12 features on one spot
    seen = Features(
        np.column_stack([np.vstack([turned, spot]), np.full((20, 2), 3.0)]).astype(np.float32),
        obj.descriptors[:20].copy(),
    )
    found = object_candidates(obj, seen, 3)
    assert found and found[0][1] == 8
    assert apply(found[0][0], (50.0, 50.0)) == pytest.approx(
        tuple(np.array([50.0, 50.0]) @ rotation.T + (600, 400)), abs=0.5
    )
    assert all(0.67 <= np.hypot(t[0, 0], t[1, 0]) <= 1.5 for t, _ in found)


def test_the_dictionaries_are_searched_for_the_object_in_view_and_for_what_the_tutor_moved(recorded):
    demo, _ = recorded
    with world_with(Placement(0.5, 0.0, 2.0)) as world:
        before = look(world)
        found = identify(demo, before, extract_features(before))
        assert found is not None and found[0] == 0 and found[1].score > 0.2
        world.tutor_place("A", Placement(0.38, 0.2, -1.0))
        assert identify_moved(demo, before, look(world), [0]) == 0
        world.tutor_place("B", Placement(0.6, -0.2, 0.0))
        assert identify_moved(demo, look(world), look(world), [0]) is None  # nothing moved between these two


def test_an_observation_pair_without_a_change_is_an_input_error():
    with world_with(FROM) as world:
        image = look(world)
        recorder = Recorder(TableModel(TableView(world)))
    with pytest.raises(InputError, match="keep the object in view"):
        changed_region(image, image)
    with pytest.raises(InputError, match="pre-place observation"):
        recorder.record(image, image)  # the table model needs the pre-place view and the heights
    with pytest.raises(InputError, match="no operations"):
        recorder.demonstration()
