"""The input bounds of ``vslsp vsl3d learn`` and ``reproduce`` (docs/recordings.md, "Limits"): a
cloud file over ``--max-size MB`` (200 by default) is refused by its size before it is read, a
PLY or PCD whose header declares more points than that before they are parsed, and a
calibration's image size over a camera's before a depth image of it is made; each refusal is
exit 2, one line naming the file and saying what to do, before anything is written."""

import json

import numpy as np
import pytest
from helpers.cli import refused, vslsp

from vslsp.experiments.cloud_folders import write_cloud_recording
from vslsp.vsl3d.files import MAX_CLOUD_BYTES, write_pcd, write_ply

CALIBRATION = {
    "camera_matrix": [[500.0, 0.0, 320.0], [0.0, 500.0, 240.0], [0.0, 0.0, 1.0]],
    "image_size": [640, 480],
    "rotation": [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]],
    "translation": [0.0, 0.0, 1.0],
}


@pytest.fixture
def folder(tmp_path):
    """A folder of one operation: a real PLY pre-action cloud, the post-action one spoiled by a test."""
    folder = tmp_path / "clouds"
    folder.mkdir()
    (folder / "calibration.json").write_text(json.dumps(CALIBRATION))
    points = np.random.default_rng(0).uniform((-0.2, -0.2, 0.8), (0.2, 0.2, 0.99), (5000, 3))
    write_ply(folder / "01-pre.ply", points)
    return folder


def test_a_sparse_cloud_file_over_max_size_is_refused_by_its_size(folder, tmp_path, capsys):
    with open(folder / "01-post.ply", "wb") as file:
        file.truncate(MAX_CLOUD_BYTES + 1)  # 200 MB of nothing: never read
    err = refused(capsys, "vsl3d", "learn", folder, "--out", tmp_path / "demo")
    assert "01-post.ply: the cloud file has 200.0 MB, over the limit of 200.0 MB" in err
    assert "--max-size MB" in err and "thin the cloud out" in err
    assert not (tmp_path / "demo").exists()


def test_max_size_lowers_the_limit(folder, tmp_path, capsys):
    (folder / "01-post.ply").write_bytes((folder / "01-pre.ply").read_bytes())  # 60 kB
    err = refused(capsys, "vsl3d", "learn", folder, "--out", tmp_path / "demo", "--max-size", "0.01")
    assert "01-post.ply: the cloud file has 0.1 MB, over the limit of 0.01 MB" in err


def test_a_ply_header_declaring_too_many_points_is_refused_before_parsing(folder, tmp_path, capsys):
    header = "ply\nformat ascii 1.0\nelement vertex 100000000000\nproperty float x\nproperty float y\n"
    (folder / "01-post.ply").write_text(header + "property float z\nend_header\n0 0 1\n")
    err = refused(capsys, "vsl3d", "learn", folder, "--out", tmp_path / "demo")
    assert "01-post.ply: its header declares 1200000.0 MB of points" in err and "--max-size" in err


def test_a_compressed_pcd_declaring_a_huge_size_is_refused_before_decompressing(folder, tmp_path, capsys):
    write_pcd(folder / "01-post.pcd", np.zeros((10, 3)))
    data = (folder / "01-post.pcd").read_bytes()
    head = data[: data.index(b"DATA")] + b"DATA binary_compressed\n"
    (folder / "01-post.pcd").write_bytes(head + (8).to_bytes(4, "little") + (4_000_000_000).to_bytes(4, "little"))
    err = refused(capsys, "vsl3d", "learn", folder, "--out", tmp_path / "demo")
    assert "01-post.pcd: its header declares 4000.0 MB of points" in err


def test_a_calibration_of_a_huge_image_is_refused(folder, tmp_path, capsys):
    (folder / "01-post.ply").write_bytes((folder / "01-pre.ply").read_bytes())
    (folder / "calibration.json").write_text(json.dumps({**CALIBRATION, "image_size": [100_000, 100_000]}))
    err = refused(capsys, "vsl3d", "learn", folder, "--out", tmp_path / "demo")
    assert "calibration.json" in err and "100000x100000 is over a camera's" in err


@pytest.fixture(scope="module")
def recording(tmp_path_factory):
    """The tutor's table cleaning (seed 0) captured as PLY files."""
    folder = tmp_path_factory.mktemp("clouds")
    write_cloud_recording(0, folder, ("ply",))
    return folder


def test_reproduce_refuses_a_scene_over_max_size(recording, tmp_path, capsys):
    folder, out = recording, tmp_path / "demo"
    assert vslsp(capsys, "vsl3d", "learn", folder, "--out", out)[0] == 0
    scene = tmp_path / "scene.ply"
    with open(scene, "wb") as file:
        file.truncate(300_000_000)
    assert "scene.ply: the cloud file has 300.0 MB" in refused(capsys, "vsl3d", "reproduce", out, scene)
    err = refused(capsys, "vsl3d", "reproduce", out, folder / "01-pre.ply", "--max-size", "0.1")
    assert "01-pre.ply: the cloud file has" in err and "over the limit of 0.1 MB" in err
    code, _, err = vslsp(capsys, "vsl3d", "reproduce", out, folder / "01-pre.ply", "--max-size", "300", "--json")
    assert code == 0, err
