"""The clouds a VSL-3D report saves for a 3-D view: the demonstration's pre- and post-action scenes
with the object getObject found labelled, decimated, written as ``.npz`` files read back without pickle."""

import numpy as np
from helpers.vsl3d import LAYOUT, assert_within_bounds, demonstrate

from vslsp.sim.cloud_scene import CloudScene
from vslsp.vsl3d.cloud import voxel_downsample
from vslsp.vsl3d.pictures import CLOUD_VOXEL, MAX_CLOUD_POINTS, labelled_cloud, trial_clouds, write_clouds
from vslsp.vsl3d.vsl import get_object


def test_the_demonstrations_clouds_label_the_moved_object(tmp_path):
    with CloudScene(LAYOUT) as scene:
        pre, post, _, _ = demonstrate(scene, "teddy", 0.53, -0.04, 0.3)
        moved = get_object(pre, post)
        clouds = trial_clouds([None, moved], {})
        assert sorted(clouds) == ["demonstration_2_post", "demonstration_2_pre"]
        written = write_clouds(tmp_path, clouds)["clouds"]
        assert written == ["clouds/demonstration_2_pre.npz", "clouds/demonstration_2_post.npz"]
        with np.load(tmp_path / written[1], allow_pickle=False) as data:
            points, labels, caption = data["points"], data["labels"], str(data["caption"])
        assert points.dtype == np.float32 and labels.shape == (len(points),)
        assert_within_bounds(points[labels == 1], scene, "teddy")  # the object where the tutor put it
        assert "post-action" in caption
    assert len(points) < len(post.points) / 2  # decimated
    assert (labels == 1).sum() == len(voxel_downsample(moved.post.points, CLOUD_VOXEL)) < len(labels) / 2


def test_a_cloud_is_decimated_and_keeps_its_object():
    scene = np.random.default_rng(0).uniform(0, 0.5, (200_000, 3))
    found = scene[scene[:, 0] < 0.05]
    cloud = labelled_cloud(scene, found, "a test")
    assert len(cloud["points"]) <= MAX_CLOUD_POINTS
    kept = cloud["points"][cloud["labels"] == 1]
    assert len(kept) and kept[:, 0].max() < 0.05 + CLOUD_VOXEL
    rest = cloud["points"][cloud["labels"] == 0]
    assert rest[:, 0].min() > 0.05 - CLOUD_VOXEL  # the object's points are not in the scene twice
