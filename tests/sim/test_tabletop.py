"""The tabletop world of the original VSL: camera, textured items, and the Panda's
pick-and-place, checked against the simulator's ground truth."""

from __future__ import annotations

import json

import cv2
import numpy as np
import pytest

from vslsp.errors import InputError
from vslsp.sim.quiet import quiet
from vslsp.sim.tabletop import (
    TABLE_CENTRE,
    TABLE_COLOUR,
    TABLE_HALF,
    WORKSPACE_X,
    WORKSPACE_Y,
    Item,
    Placement,
    TabletopWorld,
)

with quiet():
    import pybullet as pb

TILE = (0.06, 0.06, 0.012)


def picture(seed: int, size: tuple[int, int] = (128, 128)) -> np.ndarray:
    """A texture SIFT can hold on to: random coloured blocks and circles on white, (H, W, 3)."""
    rng = np.random.default_rng(seed)
    image = np.full((*size, 3), 255, np.uint8)
    for _ in range(14):
        x, y = rng.integers(0, size[1] - 20), rng.integers(0, size[0] - 20)
        colour = tuple(int(c) for c in rng.integers(0, 200, 3))
        if rng.random() < 0.5:
            cv2.rectangle(
                image, (int(x), int(y)), (int(x + rng.integers(8, 30)), int(y + rng.integers(8, 30))), colour, -1
            )
        else:
            cv2.circle(image, (int(x + 10), int(y + 10)), int(rng.integers(4, 12)), colour, -1)
    return image


def tile(name: str, seed: int = 0, **kwargs) -> Item:
    return Item(name, TILE, picture(seed), **kwargs)


def turn_error(a: float, b: float) -> float:
    return float(abs(np.angle(np.exp(1j * (a - b)))))


def test_observe_is_a_1280x960_rgb_image_and_the_same_layout_gives_the_same_bytes_and_outcomes():
    layout = [(tile("A", 1), Placement(0.40, 0.10, 0.3)), (tile("B", 2), Placement(0.55, -0.12, -0.4))]
    with TabletopWorld(layout) as first, TabletopWorld(layout) as second:
        image = first.observe()
        assert image.shape == (960, 1280, 3) and image.dtype == np.uint8
        assert np.array_equal(image, second.observe())
        assert np.array_equal(image, first.observe())
        moves = [world.pick_and_place((0.40, 0.10, 0.3), (0.50, 0.20, -0.9)) for world in (first, second)]
        assert np.array_equal(moves[0].hand_path, moves[1].hand_path) and moves[0].ok
        assert first.pose("A") == second.pose("A")
        assert np.array_equal(first.observe(), second.observe())


def test_the_parked_arm_is_out_of_view_and_the_table_fills_the_image():
    with TabletopWorld([]) as world:
        image = world.observe().astype(int)
    # An empty table is one shade everywhere: no arm, no table edge in view.
    assert np.abs(image - np.median(image.reshape(-1, 3), axis=0)).max() <= 12


def test_the_table_drawn_as_a_backdrop_looks_like_the_rasterised_table():
    layout = [
        (tile("A", 1), Placement(0.40, 0.10, 0.3)),
        (tile("B", 2), Placement(0.55, -0.10, 0.0)),
        (tile("C", 3), Placement(0.55, -0.10, 0.5, on="B")),
    ]
    with TabletopWorld(layout) as world:
        image = world.observe()
        depth = world.camera.render(world.client, world.backdrop)[1]
        c = world.client  # now rasterise the table top as well, and look again without the backdrop
        visual = pb.createVisualShape(pb.GEOM_BOX, halfExtents=TABLE_HALF, rgbaColor=TABLE_COLOUR, physicsClientId=c)
        pb.createMultiBody(0, -1, visual, [*TABLE_CENTRE, -TABLE_HALF[2]], physicsClientId=c)
        rasterised, rasterised_depth = world.camera.render(c)
    differing = np.any(image != rasterised, axis=2)
    assert differing.sum() <= 1e-4 * differing.size  # depth-test ties where an item's edge meets the table
    assert np.abs(depth - rasterised_depth).max() < 1e-3


def test_pixel_and_table_coordinates_round_trip_over_the_workspace_with_the_robot_at_the_bottom():
    with TabletopWorld([]) as world:
        for x in np.linspace(*WORKSPACE_X, 5):
            for y in np.linspace(*WORKSPACE_Y, 5):
                for z in (0.0, 0.05):
                    u, v = world.table_to_pixel(x, y, z)
                    assert 0 <= u < world.WIDTH and 0 <= v < world.HEIGHT
                    assert np.allclose(world.pixel_to_table(u, v, z), (x, y), atol=1e-9)
        near, far = world.table_to_pixel(WORKSPACE_X[0], 0.0), world.table_to_pixel(WORKSPACE_X[1], 0.0)
        left, right = world.table_to_pixel(0.5, WORKSPACE_Y[1]), world.table_to_pixel(0.5, WORKSPACE_Y[0])
        assert near[1] > far[1] and left[0] < right[0]  # robot at the bottom, its left on the left
        # Oblique, not perpendicular: the workspace's far edge looks shorter than its near edge.
        far_width = (
            world.table_to_pixel(WORKSPACE_X[1], WORKSPACE_Y[0])[0]
            - world.table_to_pixel(WORKSPACE_X[1], WORKSPACE_Y[1])[0]
        )
        near_width = (
            world.table_to_pixel(WORKSPACE_X[0], WORKSPACE_Y[0])[0]
            - world.table_to_pixel(WORKSPACE_X[0], WORKSPACE_Y[1])[0]
        )
        assert far_width < 0.9 * near_width


def test_sift_finds_a_tile_texture_in_the_render_where_the_camera_model_says_it_is():
    texture = picture(7, (160, 160))
    with TabletopWorld([(Item("T", TILE, texture), Placement(0.52, 0.08, 0.6))]) as world:
        image = world.observe()
        centre = np.array(world.table_to_pixel(0.52, 0.08, TILE[2]))
    sift = cv2.SIFT_create()
    grey = cv2.cvtColor(image, cv2.COLOR_RGB2GRAY)
    scene_points, scene_descriptors = sift.detectAndCompute(grey, None)
    near = [p for p in scene_points if np.linalg.norm(np.array(p.pt) - centre) < 60]
    assert len(near) >= 15
    texture_points, texture_descriptors = sift.detectAndCompute(cv2.cvtColor(texture, cv2.COLOR_RGB2GRAY), None)
    pairs = cv2.BFMatcher().knnMatch(texture_descriptors, scene_descriptors, k=2)
    good = [m for m, n in pairs if m.distance < 0.75 * n.distance]
    assert len(good) >= 10
    source = np.float32([texture_points[m.queryIdx].pt for m in good])
    target = np.float32([scene_points[m.trainIdx].pt for m in good])
    homography, inliers = cv2.findHomography(source, target, cv2.RANSAC, 3.0)
    assert inliers.sum() >= 8
    seen = cv2.perspectiveTransform(np.float32([[[80.0, 80.0]]]), homography)[0, 0]
    assert np.linalg.norm(seen - centre) < 3.0


def test_a_tile_picked_and_placed_with_a_turn_lands_on_target():
    with TabletopWorld([(tile("A"), Placement(0.42, 0.12, 0.2)), (tile("B", 1), Placement(0.62, 0.0))]) as world:
        result = world.pick_and_place((0.42, 0.12, 0.2), (0.55, -0.18, 0.2 + 1.3))
        x, y, z, yaw = world.pose("A")
        assert result.ok and result.diagnosis is None and result.held == "A"
        assert np.hypot(x - 0.55, y + 0.18) < 0.01 and abs(z) < 0.002
        assert turn_error(yaw, 0.2 + 1.3) < np.radians(5.0)
        assert np.allclose(world.pose("B")[:2], (0.62, 0.0), atol=1e-3)  # the neighbour stays
        assert result.hand_path.ndim == 2 and result.hand_path.shape[1] == 4 and len(result.hand_path) > 50
        assert result.duration_s > 1.0
        record = json.loads(json.dumps(result.to_dict()))  # the record survives JSON
        assert record["ok"] and record["held"] == "A" and len(record["hand_path"]) == len(result.hand_path)


def test_pick_and_place_turns_the_item_the_long_way_round_when_asked():
    with TabletopWorld([(tile("A"), Placement(0.45, 0.0, 0.0))]) as world:
        assert world.pick_and_place((0.45, 0.0, 0.0), (0.45, 0.15, -2.8)).ok
        assert turn_error(world.pose("A")[3], -2.8) < np.radians(5.0)
        assert np.hypot(world.pose("A")[0] - 0.45, world.pose("A")[1] - 0.15) < 0.01


def test_items_stack_with_placement_on_and_with_pick_and_place_onto_another_item():
    base = Item("base", (0.16, 0.12, 0.01), picture(3), movable=False)
    disk = Item("disk", (0.09, 0.05, 0.02), picture(4), mass=0.08)
    layout = [
        (base, Placement(0.60, 0.15)),
        (disk, Placement(0.60, 0.15, 0.0, on="base")),
        (Item("cube", (0.05, 0.05, 0.05), picture(5)), Placement(0.40, -0.15, 0.3)),
    ]
    with TabletopWorld(layout) as world:
        assert world.pose("disk")[2] == pytest.approx(0.01, abs=1e-3)
        # The disk is grasped across its 5 cm side and put on the cube.
        result = world.pick_and_place((0.60, 0.15, np.pi / 2), (0.40, -0.15, np.pi / 2 + 0.3))
        x, y, z, yaw = world.pose("disk")
        assert result.ok and result.held == "disk"
        assert np.hypot(x - 0.40, y + 0.15) < 0.01 and z == pytest.approx(0.05, abs=2e-3)
        assert turn_error(yaw, 0.3) < np.radians(5.0)
        assert world.pose("base") == pytest.approx((0.60, 0.15, 0.0, 0.0), abs=1e-6)


def test_a_grasp_with_a_given_width_takes_a_cube_from_between_close_neighbours():
    layout = [
        (Item("cube", (0.05, 0.05, 0.05), picture(9)), Placement(0.50, 0.0)),
        (tile("L", 1), Placement(0.50, 0.075)),
        (tile("R", 2), Placement(0.50, -0.075)),
    ]
    with TabletopWorld(layout) as world:
        result = world.pick_and_place((0.50, 0.0, np.pi / 2), (0.40, 0.20, np.pi / 2), grasp_width=0.05)
        assert result.ok and result.held == "cube"
        assert np.hypot(world.pose("cube")[0] - 0.40, world.pose("cube")[1] - 0.20) < 0.01
        for name, y in (("L", 0.075), ("R", -0.075)):  # the fingers came down between them
            assert np.allclose(world.pose(name)[:2], (0.50, y), atol=1e-3)


def test_an_item_put_next_to_a_landmark_lands_flat_on_target():
    # The closed fingertips come down 2-3.5 cm either side of the block, over the 4 mm baseline
    # 3 cm away: the grip is taken high enough for them to clear it.
    baseline = Item("baseline", (0.025, 0.34, 0.004), picture(10), movable=False)
    block = Item("B", (0.04, 0.055, 0.03), picture(11))
    with TabletopWorld([(baseline, Placement(0.6775, 0.0)), (block, Placement(0.40, 0.20, 2.9))]) as world:
        assert world.pick_and_place((0.40, 0.20, 2.9), (0.635, 0.06, 0.0)).ok
        x, y, z, yaw = world.pose("B")
        assert np.hypot(x - 0.635, y - 0.06) < 0.005 and abs(z) < 1e-3 and turn_error(yaw, 0.0) < np.radians(2.0)
        assert world.pose("baseline") == pytest.approx((0.6775, 0.0, 0.0, 0.0), abs=1e-6)


def test_the_top_disk_of_a_tower_is_taken_alone():
    base = Item("base", (0.12, 0.12, 0.01), picture(12), movable=False)
    sizes = {"disk-3": (0.09, 0.045, 0.025), "disk-2": (0.075, 0.045, 0.025), "disk-1": (0.06, 0.045, 0.025)}
    layout = [(base, Placement(0.53, 0.24))]
    for (name, size), below in zip(sizes.items(), ("base", "disk-3", "disk-2")):
        layout.append((Item(name, size, picture(len(layout))), Placement(0.53, 0.24, 0.0, on=below)))
    with TabletopWorld(layout) as world:
        result = world.pick_and_place((0.53, 0.24, np.pi / 2), (0.53, -0.01, np.pi / 2))
        assert result.ok and result.held == "disk-1"
        assert world.pose("disk-1")[:3] == pytest.approx((0.53, -0.01, 0.0), abs=0.005)
        assert world.pose("disk-2")[:3] == pytest.approx((0.53, 0.24, 0.035), abs=0.002)  # left on the tower


def test_a_pick_where_nothing_lies_is_a_failed_grasp_and_moves_nothing():
    with TabletopWorld([(tile("A"), Placement(0.40, 0.10))]) as world:
        before = world.pose("A")
        result = world.pick_and_place((0.55, -0.10, 0.0), (0.40, 0.10, 0.0))
        assert not result.ok and result.diagnosis == "grasp failed" and result.held is None
        assert world.pose("A") == pytest.approx(before, abs=1e-4)


def test_an_out_of_reach_target_is_diagnosed_before_the_arm_moves():
    with TabletopWorld([(tile("A"), Placement(0.40, 0.10))]) as world:
        result = world.pick_and_place((0.40, 0.10, 0.0), (1.20, 0.0, 0.0))
        assert not result.ok and result.diagnosis == "unreachable"
        assert result.duration_s == 0.0 and result.hand_path.shape == (0, 4)
        assert world.pose("A") == pytest.approx((0.40, 0.10, 0.0, 0.0), abs=1e-4)


def test_static_items_are_never_grasped_and_never_move():
    bin_ = Item("bin", (0.16, 0.12, 0.005), picture(6), movable=False)
    with TabletopWorld([(bin_, Placement(0.50, 0.05, 0.2)), (tile("A"), Placement(0.40, -0.15))]) as world:
        before = world.pose("bin")
        assert world.pick_and_place((0.50, 0.05, 0.0), (0.40, 0.20, 0.0)).diagnosis == "grasp failed"
        assert world.pick_and_place((0.40, -0.15, 0.0), (0.50, 0.05, 0.5)).ok  # into the bin
        assert world.pose("A")[2] == pytest.approx(0.005, abs=2e-3)
        assert world.pose("bin") == before


def test_a_slippery_item_too_heavy_for_the_grip_slips():
    brick = Item("brick", (0.05, 0.05, 0.05), picture(8), mass=0.6, friction=0.05)
    with TabletopWorld([(brick, Placement(0.45, 0.0))]) as world:
        result = world.pick_and_place((0.45, 0.0, 0.0), (0.45, 0.2, 0.0))
        assert not result.ok and result.diagnosis == "object slipped" and result.held == "brick"


def test_tutor_place_moves_an_item_and_the_world_settles():
    with TabletopWorld([(tile("A"), Placement(0.40, 0.10)), (tile("B", 1), Placement(0.60, -0.10))]) as world:
        world.tutor_place("A", Placement(0.60, -0.10, 1.0, on="B"))
        x, y, z, yaw = world.pose("A")
        assert (x, y, z) == pytest.approx((0.60, -0.10, TILE[2]), abs=1e-3) and yaw == pytest.approx(1.0, abs=1e-3)
        assert world.items() == ("A", "B")


@pytest.mark.parametrize(
    "layout, words",
    [
        ([(tile("A"), Placement(0.4, 0.0)), (tile("A"), Placement(0.5, 0.0))], "two items are named"),
        ([(tile("A"), Placement(0.4, 0.0, on="B"))], "cannot go on"),
        ([(tile("A"), Placement(float("nan"), 0.0))], "finite"),
    ],
)
def test_a_bad_layout_is_an_input_error(layout, words):
    with pytest.raises(InputError, match=words):
        TabletopWorld(layout).close()


def test_bad_items_and_poses_are_input_errors():
    with pytest.raises(InputError, match="texture"):
        Item("A", TILE, np.zeros((8, 8), np.uint8))
    with pytest.raises(InputError, match="size"):
        Item("A", (0.06, 0.06), picture(0))
    with TabletopWorld([]) as world:
        with pytest.raises(InputError, match="pick pose"):
            world.pick_and_place((0.4, 0.0), (0.5, 0.0, 0.0))
        with pytest.raises(InputError, match="no item"):
            world.pose("Z")
