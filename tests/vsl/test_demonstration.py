"""The demonstration recorder (Algorithm 1, part I) with the image-plane model: dictionaries
O^Pre, O^Post, symbols, poses, features and the policy Π, saved as JSON + PNG + npz and loaded
back; with a pre-place observation also the turn the tutor gave the object."""

import json

import numpy as np
import pytest

from vslsp.errors import InputError
from vslsp.grounding.synthetic import Square, tabletop_image
from vslsp.vsl.demonstration import Demonstration, ImagePlane
from vslsp.vsl.recorder import Recorder
from vslsp.worlds.house_roof.board import HouseWorld

SCENES = [
    [Square("red", (150, 400)), Square("blue", (450, 150), angle=20)],
    [Square("red", (160, 140), angle=10), Square("blue", (450, 150), angle=20)],  # push red
    [Square("red", (160, 140), angle=10), Square("blue", (430, 410), angle=35)],  # pull blue
]


@pytest.fixture(scope="module")
def demonstration():
    images = [tabletop_image(scene, noise=3, seed=k) for k, scene in enumerate(SCENES)]
    recorder = Recorder(ImagePlane(images[0]))
    for pre, post in zip(images, images[1:]):
        recorder.record(pre, post)
    return recorder.demonstration()


def test_each_operation_records_symbol_poses_constraints_and_action(demonstration):
    first, second = demonstration.operations
    assert demonstration.policy == ("push", "pull")
    assert (first.symbol, second.symbol) == ("red", "blue")
    assert first.constraints_pre == {"far": False} and first.constraints_post == {"far": True}
    assert np.hypot(first.pose_post.x - 160, first.pose_post.y - 140) < 1.5
    assert abs(np.degrees(second.pose_post.theta) - 35) < 3.0
    assert len(first.features) > 0 and first.object_size >= 60
    assert len(demonstration.pre_observations) == len(demonstration.post_observations) == 2


def test_a_saved_demonstration_loads_back_the_same(demonstration, tmp_path):
    path = demonstration.save(tmp_path / "demo")
    assert json.loads(path.read_text())["policy"] == ["push", "pull"]
    loaded = Demonstration.load(tmp_path / "demo")
    assert loaded.policy == demonstration.policy
    assert loaded.landmark.to_dict() == demonstration.landmark.to_dict()  # JSON keeps 0.01 px
    for a, b in zip(loaded.operations, demonstration.operations):
        assert a.grounding.to_dict() == b.grounding.to_dict()
        assert np.array_equal(a.pre_observation, b.pre_observation)
        assert np.array_equal(a.features.descriptors, b.features.descriptors)
        assert a.pose_pre.to_dict() == b.pose_pre.to_dict()
    with np.load(tmp_path / "demo" / "features.npz", allow_pickle=False) as arrays:
        assert all(arrays[key].dtype != object for key in arrays.files)


def test_loading_a_folder_that_is_not_a_demonstration_is_an_input_error(tmp_path):
    with pytest.raises(InputError, match="cannot read the demonstration"):
        Demonstration.load(tmp_path)
    (tmp_path / "demonstration.json").write_text('{"format": "something-else"}')
    with pytest.raises(InputError, match="format"):
        Demonstration.load(tmp_path)


def test_a_pre_place_observation_gives_the_turn_and_is_saved_with_the_operation(tmp_path):
    world = HouseWorld.random(2, body_turn=0.5)
    recorder = Recorder(ImagePlane(world.render()))
    roof = world.roofs[0]
    assert roof is not None
    lifted = world.with_roof(0, None)
    moved = lifted.with_roof(0, (roof[0] + 40.0, roof[1] - 30.0, roof[2] + 0.6))
    op = recorder.record(world.render(), moved.render(), lifted.render())
    assert op.turn is not None and abs(op.turn - 0.6) < np.radians(0.5)
    assert op.pre_place is not None and np.array_equal(op.pre_place, lifted.render())
    recorder.demonstration().save(tmp_path / "demo")
    (loaded,) = Demonstration.load(tmp_path / "demo").operations
    assert loaded.turn == pytest.approx(op.turn) and np.array_equal(loaded.pre_place, op.pre_place)


def test_an_empty_demonstration_is_an_input_error():
    image = tabletop_image(SCENES[0], noise=3, seed=0)
    with pytest.raises(InputError, match="no operations"):
        Recorder(ImagePlane(image)).demonstration()
