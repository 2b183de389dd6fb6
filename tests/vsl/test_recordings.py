"""VSL from a folder of pictures (docs/recordings.md): the alphabet-ordering demonstration
rendered and saved to disk as a user would, learned with ``vslsp vsl learn``, answered with
``vslsp vsl reproduce`` (pixels and table metres, a session that ends in ``{"done": true}``),
and every kind of bad input refused with exit 2 and one line naming the file."""

import json
import shutil

import cv2
import numpy as np
import pytest
from helpers.cli import refused, vslsp
from helpers.pictures import png_header

from vslsp.experiments.picture_folders import write_recording
from vslsp.vision.image import read_image, write_image
from vslsp.vsl.learned import load_learned, save_learned
from vslsp.vsl.recordings import learn, read_recording

TASK = "alphabet-ordering"


@pytest.fixture(scope="module")
def recording(tmp_path_factory):
    """The tutor's demonstration of alphabet-ordering (seed 0) photographed into a folder."""
    folder = tmp_path_factory.mktemp("recording")
    goal = write_recording(TASK, 0, folder)
    return folder, goal


@pytest.fixture(scope="module")
def demo(recording, tmp_path_factory):
    """The recording learned into a DEMO folder (as `vslsp vsl learn` writes it)."""
    folder = tmp_path_factory.mktemp("demo")
    read = read_recording(recording[0])
    save_learned(learn(read), read, folder)
    return folder


def copy_of(recording, tmp_path):
    folder = tmp_path / "copy"
    shutil.copytree(recording[0], folder)
    return folder


def test_the_folder_holds_the_documented_layout(recording):
    folder, goal = recording
    names = sorted(p.name for p in folder.iterdir())
    assert names[:3] == ["01-mid.png", "01-post.png", "01-pre.png"]
    assert "02-pre.png" not in names  # the world as operation 1 left it
    assert {"calibration.json", "names.json", "heights.json"} <= set(names)
    assert json.loads((folder / "names.json").read_text()) == list(goal.items) == ["A", "B", "C", "D"]


def test_learn_records_every_operation_with_its_annotated_picture(recording, tmp_path, capsys):
    code, out, err = vslsp(capsys, "vsl", "learn", recording[0], "--out", tmp_path / "demo", "--json")
    assert code == 0, err
    answer = json.loads(out)
    assert answer["calibrated"] and [op["name"] for op in answer["operations"]] == ["A", "B", "C", "D"]
    for op in answer["operations"]:
        assert op["features"] > 20
        assert read_image(tmp_path / "demo" / op["annotated"]).shape[2] == 3
    arrays = np.load(tmp_path / "demo" / "features.npz", allow_pickle=False)
    assert arrays["op01_descriptors"].shape[1] == 128
    learned = load_learned(tmp_path / "demo")
    assert len(learned) == 4 and learned.names == ("A", "B", "C", "D")


def test_reproduce_in_the_demonstration_scene_picks_where_the_object_lies(recording, demo, capsys):
    code, out, err = vslsp(capsys, "vsl", "reproduce", demo, recording[0] / "01-pre.png", "--json")
    assert code == 0, err
    answer = json.loads(out)
    assert answer["operation"] == 1 and answer["name"] == "A" and not answer["done"]
    learned = load_learned(demo)
    op = learned.demonstration.operations[0]
    x, y = learned.calibration.view.pixel_to_table(*op.pick_point, op.pick_z)
    assert answer["pick"]["table_m"] == pytest.approx([x, y], abs=0.003)  # the object did not move
    u, v = learned.calibration.image_pixel(x, y, op.pick_z)
    assert answer["pick"]["pixel"] == pytest.approx([u, v], abs=3.0)
    assert 0.03 < answer["grasp_width_m"] < 0.06


def test_a_session_answers_operation_after_operation_until_done(recording, demo, tmp_path, capsys):
    session = tmp_path / "session.json"
    scene = recording[0] / "01-pre.png"
    code, out, _ = vslsp(capsys, "vsl", "reproduce", demo, scene, "--step", session, "--json")
    assert code == 0 and json.loads(out)["operation"] == 1
    assert json.loads(session.read_text())["next"] == 1
    record = json.loads(session.read_text())
    session.write_text(json.dumps({**record, "next": 4}))  # the robot did all four
    code, out, _ = vslsp(capsys, "vsl", "reproduce", demo, scene, "--step", session, "--json")
    assert code == 0 and json.loads(out) == {"done": True, "operations": 4}


def test_a_missing_picture_is_named(recording, tmp_path, capsys):
    folder = copy_of(recording, tmp_path)
    (folder / "02-mid.png").unlink()
    assert "02-mid.png is missing" in refused(capsys, "vsl", "learn", folder, "--out", tmp_path / "demo")
    assert not (tmp_path / "demo").exists()  # before any work


def test_pictures_of_another_size_are_named(recording, tmp_path, capsys):
    folder = copy_of(recording, tmp_path)
    write_image(folder / "02-post.png", cv2.resize(read_image(folder / "02-post.png"), (640, 480)))
    assert "02-post.png is 640x480 px" in refused(capsys, "vsl", "learn", folder, "--out", tmp_path / "demo")


def test_operations_with_a_gap_are_named(recording, tmp_path, capsys):
    folder = copy_of(recording, tmp_path)
    for role in ("mid", "post"):
        (folder / f"04-{role}.png").rename(folder / f"06-{role}.png")
    err = refused(capsys, "vsl", "learn", folder, "--out", tmp_path / "demo")
    assert "06-" in err and "operation 4 is missing" in err


def test_a_stray_picture_is_named(recording, tmp_path, capsys):
    folder = copy_of(recording, tmp_path)
    shutil.copy(folder / "01-pre.png", folder / "01-before.png")
    assert "01-before.png" in refused(capsys, "vsl", "learn", folder, "--out", tmp_path / "demo")


@pytest.mark.parametrize(
    ("change", "says"),
    [
        (lambda c: "{", "calibration.json"),
        (lambda c: {**c, "image_size": [640, 480]}, "for images of [640, 480] px"),
        (lambda c: {**c, "rotation": [[1, 0], [0, 1]]}, '"rotation" must be 3 x 3'),
        (lambda c: {k: v for k, v in c.items() if k != "translation"}, '"translation" is missing'),
        (lambda c: {**c, "translation": [0.0, 0.0, -1.0]}, "calibration does not fit"),
    ],
)
def test_a_calibration_that_does_not_parse_or_fit_is_named(recording, tmp_path, capsys, change, says):
    folder = copy_of(recording, tmp_path)
    calibration = json.loads((folder / "calibration.json").read_text())
    changed = change(calibration)
    (folder / "calibration.json").write_text(changed if isinstance(changed, str) else json.dumps(changed))
    err = refused(capsys, "vsl", "learn", folder, "--out", tmp_path / "demo")
    assert "calibration.json" in err and says in err


def test_names_and_heights_that_do_not_fit_are_named(recording, tmp_path, capsys):
    folder = copy_of(recording, tmp_path)
    (folder / "names.json").write_text('["A", "B"]')
    assert "names.json: give a list of 4 names" in refused(capsys, "vsl", "learn", folder, "--out", tmp_path / "d")
    (folder / "names.json").unlink()
    (folder / "heights.json").write_text('[{"height": "tall"}]')
    assert "heights.json" in refused(capsys, "vsl", "learn", folder, "--out", tmp_path / "d")


def test_a_folder_that_is_no_demonstration_is_named(recording, tmp_path, capsys):
    err = refused(capsys, "vsl", "reproduce", recording[0], recording[0] / "01-pre.png")
    assert "is not a learned demonstration" in err and str(recording[0]) in err


def test_a_scene_of_another_size_or_missing_is_named(recording, demo, tmp_path, capsys):
    scene = tmp_path / "scene.png"
    write_image(scene, np.zeros((480, 640, 3), np.uint8))
    assert "scene.png is 640x480 px" in refused(capsys, "vsl", "reproduce", demo, scene)
    claimed = tmp_path / "claimed.png"  # no pixel: refused from its header, before it is decoded
    claimed.write_bytes(png_header(640, 480))
    assert "claimed.png is 640x480 px" in refused(capsys, "vsl", "reproduce", demo, claimed)
    assert "nowhere.png" in refused(capsys, "vsl", "reproduce", demo, tmp_path / "nowhere.png")


def test_a_session_of_another_demonstration_is_named(recording, demo, tmp_path, capsys):
    session = tmp_path / "session.json"
    session.write_text(
        json.dumps({"format": "vslsp-vsl-session/1", "demonstration": "/elsewhere", "next": 0, "given": []})
    )
    err = refused(capsys, "vsl", "reproduce", demo, recording[0] / "01-pre.png", "--step", session)
    assert "session.json is the session of /elsewhere" in err
