"""VSL on pictures vslsp did not render (vslsp/experiments/photo_folders.py): cards printed with
scikit-image's photographs on a photographed table, through a tilted camera with lens
distortion, blur, noise and JPEG, written as a user's recording folder, learned with
``vslsp vsl learn`` and reproduced by the closed loop of ``vslsp vsl reproduce --step``; each
card judged on the ground truth (1 cm / 5 deg of its demonstrated pose beside the card before)."""

import json
from dataclasses import replace

import numpy as np
import pytest
from helpers.cli import vslsp

pytest.importorskip("skimage")

from vslsp.experiments.photo_folders import WORKSPACE, closed_loop, photo_task, write_recording  # noqa: E402

POSITION, ANGLE = 0.01, 5.0  # m, deg


def run(tmp_path, capsys, seed: int, operations: int, task=None, calibration=None) -> list[dict]:
    task = task or photo_task(seed, operations)
    goal = write_recording(task, seed, tmp_path / "recording")
    if calibration is not None:
        (tmp_path / "recording" / "calibration.json").write_text(json.dumps(calibration))
    code, _, err = vslsp(capsys, "vsl", "learn", tmp_path / "recording", "--out", tmp_path / "demo", "--json")
    assert code == 0, err
    (tmp_path / "scenes").mkdir()

    def ask(scene):
        _, out, _ = vslsp(capsys, "vsl", "reproduce", tmp_path / "demo", scene, "--step", tmp_path / "s.json", "--json")
        return json.loads(out)

    return closed_loop(task, seed, goal, tmp_path / "scenes", ask)


def test_the_recording_is_a_users_folder_of_jpeg_photographs(tmp_path):
    task = photo_task(0, 2)
    write_recording(task, 0, tmp_path)
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == [
        "01-mid.jpg",
        "01-post.jpg",
        "01-pre.jpg",
        "02-mid.jpg",
        "02-post.jpg",
        "calibration.json",
        "names.json",
    ]
    calibration = json.loads((tmp_path / "calibration.json").read_text())
    assert calibration["distortion"][0] < 0 and calibration["image_size"] == [1024, 768]
    tilt = np.degrees(np.arccos(-task.camera.rotation[2, 2]))  # the camera's axis against the table's down
    assert 10.0 <= tilt <= 20.0


def test_the_same_seed_takes_the_same_pictures(tmp_path):
    first, second = tmp_path / "a", tmp_path / "b"
    write_recording(photo_task(3, 1), 3, first)
    write_recording(photo_task(3, 1), 3, second)
    assert (first / "01-post.jpg").read_bytes() == (second / "01-post.jpg").read_bytes()


def test_two_operations_are_placed_on_the_ground_truth(tmp_path, capsys):
    done = run(tmp_path, capsys, 0, 2)
    assert [op["operation"] for op in done] == [1, 2]
    for op in done:
        assert op["position_error_m"] <= POSITION and op["angle_error_deg"] <= ANGLE, op


def test_a_homography_calibration_places_as_well(tmp_path, capsys):
    """The camera of seed 0 without lens distortion, told as the homography of the table plane
    (what `vslsp vsl calibrate --points` writes): heights make no difference to flat cards."""
    task = photo_task(0, 2)
    camera = replace(task.camera, distortion=np.zeros(5))
    plane = camera.matrix @ np.column_stack([camera.rotation[:, 0], camera.rotation[:, 1], camera.translation])
    homography = np.linalg.inv(plane)
    calibration = {
        "homography": (homography / homography[2, 2]).tolist(),
        "image_size": [1024, 768],
        "workspace": WORKSPACE,
    }
    done = run(tmp_path, capsys, 0, 2, replace(task, camera=camera), calibration)
    assert [op["operation"] for op in done] == [1, 2]
    for op in done:
        assert op["position_error_m"] <= POSITION and op["angle_error_deg"] <= ANGLE, op


@pytest.mark.slow
def test_the_closed_loop_completes_five_operations_from_photographs(tmp_path, capsys):
    done = run(tmp_path, capsys, 5, 5)
    assert [op.get("operation") for op in done] == [1, 2, 3, 4, 5]
    for op in done:
        assert op["position_error_m"] <= POSITION and op["angle_error_deg"] <= ANGLE, op
