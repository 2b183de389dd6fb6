"""The demonstration recorder (Algorithm 1, part I): dictionaries O^Pre, O^Post, symbols,
poses, features and the policy Π, saved as JSON + PNG + npz and loaded back."""

import json

import numpy as np
import pytest

from vslsp.errors import InputError
from vslsp.grounding.synthetic import Square, tabletop_image
from vslsp.vsl.demonstration import Demonstration, DemonstrationRecorder

SCENES = [
    [Square("red", (150, 400)), Square("blue", (450, 150), angle=20)],
    [Square("red", (160, 140), angle=10), Square("blue", (450, 150), angle=20)],  # push red
    [Square("red", (160, 140), angle=10), Square("blue", (430, 410), angle=35)],  # pull blue
]


@pytest.fixture(scope="module")
def demonstration():
    images = [tabletop_image(scene, noise=3, seed=k) for k, scene in enumerate(SCENES)]
    recorder = DemonstrationRecorder(images[0])
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
