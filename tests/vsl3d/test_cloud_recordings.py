"""VSL-3D from a folder of clouds (docs/recordings.md, "VSL-3D"): a rendered capture written as
PLY (binary and ASCII), PCD (binary and ASCII), ``.npz`` and a millimetre depth PNG reads back as
the same world cloud; the table-cleaning demonstration captured into files, learned with
``vslsp vsl3d learn`` and reproduced in the reshuffled scene in a closed loop, where each answer
is executed by the Panda and the scene captured again; and bad input refused with exit 2 and one
line naming the file."""

import json
import shutil

import numpy as np
import pytest
from helpers.cli import vslsp

from vslsp.experiments.cloud_folders import FORMATS, calibration, closed_loop, write_capture, write_cloud_recording
from vslsp.sim.cloud_scene import CloudScene
from vslsp.vsl3d.cloud import DepthCamera
from vslsp.vsl3d.recordings import calibration_from_dict, read_world

TOLERANCE_M, TOLERANCE_DEG = 0.01, 5.0


@pytest.fixture(scope="module")
def capture():
    """One capture of the duck and the teddy on the table, and its calibration."""
    with CloudScene({"duck": (0.5, -0.1, 0.7), "teddy": (0.6, 0.12, -0.4)}, tray=False) as scene:
        image = scene.capture()
    return image, calibration(DepthCamera.of(image.camera))


@pytest.mark.parametrize("form", FORMATS)
def test_every_file_form_reads_back_as_the_world_the_sensor_saw(capture, form, tmp_path):
    image, data = capture
    camera = calibration_from_dict(data)
    reference = read_world(write_capture(image, tmp_path / "ref", "npz"), camera)
    world = read_world(write_capture(image, tmp_path / "scene", form), camera)
    assert len(reference.points) > 1000
    if form == "depth":  # the PNG keeps whole millimetres: a few voxels fall to the next one
        assert np.abs(world.depth - image.depth).max() <= 0.0005 + 1e-6
        assert abs(len(world.points) - len(reference.points)) < 0.05 * len(reference.points)
        return
    assert len(world.points) == len(reference.points)
    assert np.abs(world.points - reference.points).max() < 1e-5
    assert np.abs(world.depth - image.depth).max() < 1e-5


@pytest.fixture(scope="module")
def recording(tmp_path_factory):
    """The tutor's table cleaning (seed 0) captured as PLY and PCD files, and its truth."""
    folder = tmp_path_factory.mktemp("clouds")
    truth = write_cloud_recording(0, folder, ("ply", "pcd"))
    return folder, truth


@pytest.mark.slow
def test_the_closed_loop_from_cloud_files_puts_every_object_where_the_tutor_did(recording, tmp_path, capsys):
    folder, truth = recording
    assert sorted(p.name for p in folder.iterdir())[:4] == ["01-post.ply", "01-pre.ply", "02-post.pcd", "03-post.ply"]
    code, out, err = vslsp(capsys, "vsl3d", "learn", folder, "--out", tmp_path / "demo", "--json")
    assert code == 0, err
    assert [op["name"] for op in json.loads(out)["operations"]] == ["duck", "teddy", "duckling"]
    session = tmp_path / "session.json"

    def ask(scene):
        code, out, err = vslsp(capsys, "vsl3d", "reproduce", tmp_path / "demo", scene, "--step", session, "--json")
        answer = json.loads(out)
        assert (code == 0) == ("error" not in answer), err
        return answer

    done = closed_loop(0, truth, tmp_path, ask, form="pcd")
    assert [op["name"] for op in done] == ["duck", "teddy", "duckling"]
    for op in done:
        assert op["held"] == op["name"]
        assert op["found_error_mm"] < TOLERANCE_M * 1000 and op["found_error_deg"] < TOLERANCE_DEG, op
        assert op["final_error_mm"] < TOLERANCE_M * 1000 and op["final_error_deg"] < TOLERANCE_DEG, op
    assert ask(tmp_path / "scene-04.pcd")["done"]  # the session is over


def test_an_answer_tells_the_object_and_its_place_in_both_frames(recording, tmp_path, capsys):
    folder, truth = recording
    assert vslsp(capsys, "vsl3d", "learn", folder, "--out", tmp_path / "demo")[0] == 0
    code, out, err = vslsp(capsys, "vsl3d", "reproduce", tmp_path / "demo", folder / "01-pre.ply", "--json")
    assert code == 0, err
    answer = json.loads(out)
    assert answer["operation"] == 1 and answer["name"] == "duck"
    pose = np.asarray(answer["pick"]["pose"])  # the demonstration's own scene: the object where it was
    assert np.abs(pose - np.eye(4)).max() < 0.01
    camera = calibration_from_dict(json.loads((folder / "calibration.json").read_text())).camera
    centre = np.asarray(answer["pick"]["centroid_camera_m"])
    table = camera.pose[:3, :3] @ centre + camera.pose[:3, 3]
    assert np.allclose(table, answer["pick"]["centroid_m"], atol=1e-4)
    assert answer["place"]["centroid_m"][2] > 0.02 and len(answer["motion_camera"]) == 4


def copy_of(recording, tmp_path):
    folder = tmp_path / "copy"
    shutil.copytree(recording[0], folder)
    return folder


@pytest.mark.parametrize(
    "spoil, named",
    [
        (lambda f: (f / "01-pre.ply").unlink(), "01-pre.ply"),  # a missing cloud
        (lambda f: (f / "03-post.ply").write_text("ply\nformat ascii 1.0\nelement vertex 0\n"), "03-post.ply"),
        (lambda f: (f / "03-post.ply").write_bytes(b"not a ply file"), "03-post.ply"),  # unreadable
        (lambda f: (f / "01-pre.ply").write_bytes(b"ply\nformat ascii 1.0\nelement vertex 0\n"
                                                  b"property float x\nproperty float y\nproperty float z\n"
                                                  b"end_header\n"), "01-pre.ply"),  # empty
        (lambda f: (f / "calibration.json").write_text('{"camera_matrix": 1}'), "calibration.json"),
        (lambda f: (f / "calibration.json").unlink(), "calibration.json"),
        (lambda f: (f / "05-post.ply").write_bytes((f / "03-post.ply").read_bytes()), "05-post.ply"),  # a gap
        (lambda f: (f / "names.json").write_text('["duck"]'), "names.json"),
    ],
)  # fmt: skip
def test_bad_input_exits_2_naming_the_file(recording, tmp_path, capsys, spoil, named):
    folder = copy_of(recording, tmp_path)
    spoil(folder)
    code, out, err = vslsp(capsys, "vsl3d", "learn", folder, "--out", tmp_path / "demo")
    assert code == 2
    assert named in err and len(err.strip().splitlines()) == 1, err
    assert not (tmp_path / "demo").exists()  # refused before any work


def test_a_scene_that_is_not_a_cloud_exits_2_naming_it(recording, tmp_path, capsys):
    folder, _ = recording
    assert vslsp(capsys, "vsl3d", "learn", folder, "--out", tmp_path / "demo")[0] == 0
    for scene, text in ((tmp_path / "scene.ply", "garbage"), (tmp_path / "scene.pcd", "")):
        scene.write_text(text)
        code, out, err = vslsp(capsys, "vsl3d", "reproduce", tmp_path / "demo", scene, "--json")
        assert code == 2 and scene.name in json.loads(out)["error"]
    code, _, err = vslsp(capsys, "vsl3d", "reproduce", folder, folder / "01-pre.ply")
    assert code == 2 and "vsl3d-demonstration.json" in err
