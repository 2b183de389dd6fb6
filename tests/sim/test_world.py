"""The simulated world: determinism, cameras, settled cubes, the tutor."""

import numpy as np
import pytest

from vslsp.errors import InputError
from vslsp.sim import CubeSpec, LandmarkSpec, LineWorld, SceneSpec


@pytest.fixture(scope="module")
def table_world():
    with LineWorld(SceneSpec.random(5), robot=False) as world:
        yield world


def test_same_seed_gives_byte_identical_images():
    images = []
    for _ in range(2):
        with LineWorld(seed=11) as world:
            images.append(world.observe("head", 320, 240).rgb)
    assert np.array_equal(images[0], images[1])


def test_different_seeds_give_different_scenes():
    assert SceneSpec.random(1) != SceneSpec.random(2)
    with LineWorld(seed=1, robot=False) as a, LineWorld(seed=2, robot=False) as b:
        assert not np.array_equal(a.observe("overhead", 160, 120).rgb, b.observe("overhead", 160, 120).rgb)


def test_cubes_rest_on_the_table_where_the_spec_puts_them(table_world):
    for cube in table_world.spec.cubes:
        x, y, _ = table_world.cube_pose(cube.name)
        assert abs(table_world.cube_height(cube.name) - cube.size / 2) < 1e-3
        assert np.hypot(x - cube.x, y - cube.y) < 2e-3


def test_random_scene_respects_the_requested_sides():
    spec = SceneSpec.random(3, colours=("red", "green", "blue"), far=(True, False, True))
    sides = [spec.landmark.signed_distance([c.x, c.y]) > 0 for c in spec.cubes]
    assert sides == [True, False, True]


def test_scene_json_round_trip(tmp_path):
    spec = SceneSpec.random(4)
    spec.save(tmp_path / "scene.json")
    assert SceneSpec.load(tmp_path / "scene.json") == spec


def test_bad_scene_input_is_a_clear_error(tmp_path):
    with pytest.raises(InputError, match="unknown colour"):
        CubeSpec("x", "teal", 0.2, 0.0)
    (tmp_path / "bad.json").write_text('{"cubes": [{"name": 1}]}')
    with pytest.raises(InputError, match="not a scene description"):
        SceneSpec.load(tmp_path / "bad.json")


@pytest.mark.parametrize("camera", ["head", "overhead"])
def test_pixel_table_pixel_round_trip_within_a_pixel(table_world, camera):
    view = table_world.camera(camera)
    rng = np.random.default_rng(0)
    for u, v in rng.uniform([20, 20], [620, 460], size=(50, 2)):
        x, y = view.pixel_to_table(u, v)
        assert np.hypot(*np.subtract(view.table_to_pixel(x, y), (u, v))) < 1.0


@pytest.mark.parametrize("camera", ["head", "overhead"])
def test_the_camera_model_matches_the_render(camera):
    """The top face of a cube is seen where the camera model projects it."""
    spec = SceneSpec((CubeSpec("green", "green", 0.24, -0.05),), LandmarkSpec(0.2, 0.0))
    with LineWorld(spec, robot=False, textured=False) as world:  # a plain face: its centre pixel is green
        observation = world.observe(camera)
        rgb = observation.rgb.astype(int)
        mask = (rgb[:, :, 1] > 120) & (rgb[:, :, 0] < 80) & (rgb[:, :, 2] < 100)
        rows, cols = np.nonzero(mask)
        top = observation.camera.table_to_pixel(0.24, -0.05, z=world_top(world))
        assert mask[int(top[1]), int(top[0])]
        assert abs(cols.mean() - top[0]) < 6


def world_top(world):
    return 0.58 + world.spec.cubes[0].size


def test_tutor_relocates_a_cube_within_5_mm():
    # A world of its own: moving a cube in the shared module world would change what the other tests see.
    with LineWorld(SceneSpec.random(5), robot=False) as world:
        name = world.spec.cubes[0].name
        world.tutor.relocate(name, 0.30, -0.12)
        x, y, _ = world.cube_pose(name)
        assert np.hypot(x - 0.30, y + 0.12) < 0.005
        assert abs(world.cube_height(name) - 0.025) < 1e-3
