"""``vslsp ground PRE POST``: JSON on stdout, the overlay PNG, user predicates, exit code 2 for
bad input (with an {"error": ...} object under --json), checked before any work."""

import json
import textwrap
from pathlib import Path

import cv2
import numpy as np
import pytest
from helpers.cli import vslsp_process as _vslsp

from vslsp.grounding.synthetic import Square, tabletop_image
from vslsp.vision.image import read_image, write_image


@pytest.fixture(scope="module")
def images(tmp_path_factory):
    folder = tmp_path_factory.mktemp("ground")
    still = Square("blue", (500, 420))
    write_image(folder / "pre.png", tabletop_image([Square("purple", (200, 150)), still]))
    write_image(folder / "post.png", tabletop_image([Square("purple", (220, 410)), still]))
    write_image(folder / "small.png", tabletop_image([still], size=(320, 240)))
    write_image(folder / "both.png", tabletop_image([Square("purple", (220, 410)), Square("blue", (480, 130))]))
    (folder / "notes.png").write_text("not an image")
    cv2.imwrite(str(folder / "wide.png"), np.full((40, 20000, 3), 200, np.uint8))
    cv2.imwrite(str(folder / "huge.jpg"), np.full((8000, 6000, 3), 200, np.uint8))
    (folder / "preds.py").write_text(
        textwrap.dedent("""
        from vslsp.grounding import predicate, register
        from vslsp.grounding.relations import LEFT_OF

        register(LEFT_OF)

        @predicate("right-half")
        def right_half(obj, scene):
            return obj.x > scene.width / 2
    """)
    )
    (folder / "raises.py").write_text(
        textwrap.dedent("""
        from vslsp.grounding import predicate

        @predicate("broken")
        def broken(obj, scene):
            return obj.colour == "red"
    """)
    )
    (folder / "not_bool.py").write_text(
        textwrap.dedent("""
        from vslsp.grounding import predicate

        @predicate("distance", arity=2)
        def distance(a, b, scene):
            return abs(a.x - b.x)
    """)
    )
    (folder / "syntax.py").write_text("from vslsp.grounding import predicate\n\ndef oops(:\n")
    (folder / "empty.py").write_text("x = 1\n")
    (folder / "far_again.py").write_text(
        textwrap.dedent("""
        from vslsp.grounding import predicate

        @predicate("far")
        def mine(obj, scene):
            return obj.y < 100
    """)
    )
    return folder


def test_json_output_and_overlay(images):
    result = _vslsp("ground", images / "pre.png", images / "post.png", "--json", "--overlay", images / "o.png")
    assert result.returncode == 0, result.stderr
    data = json.loads(result.stdout)
    assert data["object"]["name"] == "purple" and data["action"] == "pull"
    assert data["far"] == {"pre": True, "post": False}
    assert read_image(images / "o.png").shape == (480, 1280, 3)


def test_text_output_and_robot_side(images):
    result = _vslsp("ground", images / "pre.png", images / "post.png", "--robot-side", "top")
    assert result.returncode == 0 and "purple" in result.stdout and "action: push" in result.stdout


@pytest.mark.parametrize(
    "pre, post, message, code",
    [
        ("pre.png", "pre.png", "nothing moved", 1),  # usable images, no answer: a failed task
        ("pre.png", "small.png", "differ in size", 2),
        ("pre.png", "missing.png", "cannot read", 2),
        ("notes.png", "post.png", "not an image", 2),
        ("pre.png", "both.png", "more than one object moved (purple left", 1),
    ],
)
def test_bad_input_exits_with_a_message_and_no_traceback(images, pre, post, message, code):
    result = _vslsp("ground", images / pre, images / post, "--json")
    assert result.returncode == code
    assert message in result.stderr and "Traceback" not in result.stderr
    assert message in json.loads(result.stdout)["error"]


def test_predicates_file_adds_the_true_atoms_before_and_after(images):
    result = _vslsp("ground", images / "pre.png", images / "post.png", "--predicates", images / "preds.py", "--json")
    assert result.returncode == 0, result.stderr
    atoms = json.loads(result.stdout)["atoms"]
    # purple (200, 150) -> (220, 410) crosses the line; blue stays at (500, 420): the right half.
    assert atoms["pre"] == ["(far purple)", "(left-of purple blue)", "(right-half blue)"]
    assert atoms["post"] == ["(left-of purple blue)", "(right-half blue)"]
    text = _vslsp("ground", images / "pre.png", images / "post.png", "--predicates", images / "preds.py")
    assert "post: (left-of purple blue) (right-half blue)" in text.stdout


@pytest.mark.parametrize(
    "args, message",
    [
        (("wide.png", "post.png"), "is 20000x40 pixels; perception takes images of at least 32 and at most 8192"),
        (("pre.png", "huge.jpg"), "is 6000x8000 pixels"),
        (("pre.png", "post.png", "--overlay", "x.txt"), "give a file name ending in .png"),
        (("pre.png", "post.png", "--overlay", "noext"), "give a file name ending in .png"),
        (("pre.png", "post.png", "--overlay", "nowhere/o.png"), "does not exist"),
        (
            ("pre.png", "post.png", "--predicates", "raises.py"),
            "predicate broken raised AttributeError: 'SceneObject' object has no attribute 'colour' while grounding",
        ),
        (("pre.png", "post.png", "--predicates", "not_bool.py"), "predicate distance returned float"),
        (("pre.png", "post.png", "--predicates", "syntax.py"), "syntax.py, line 3: SyntaxError"),
        (("pre.png", "post.png", "--predicates", "empty.py"), "registers no predicate"),
        (("pre.png", "post.png", "--predicates", "far_again.py"), "predicate far is defined twice"),
        (("pre.png", "post.png", "--predicates", "missing.py"), "no such file"),
        (("pre.png", "post.png", "--predicates", "notes.png"), "must be a Python file"),
    ],
)
def test_bad_sizes_overlays_and_predicates_exit_2_before_any_work(images, args, message):
    paths = [images / a if a.endswith((".png", ".jpg", ".py")) and "/" not in a else a for a in args]
    paths = [images / a if a == "nowhere/o.png" else a for a in paths]
    result = _vslsp("ground", *paths, "--json")
    assert result.returncode == 2, result.stderr
    assert message in result.stderr and "Traceback" not in result.stderr
    assert message in json.loads(result.stdout)["error"]
    assert not (images / "x.txt").exists() and not (images / "noext").exists()


@pytest.mark.parametrize(
    "args, message",
    [
        (("--robot-side", "under"), "Invalid value for '--robot-side'"),
        (("--colour", "red"), "No such option '--colour'"),
    ],
)
def test_usage_errors_under_json_print_json(images, args, message):
    result = _vslsp("ground", images / "pre.png", images / "post.png", "--json", *args)
    assert result.returncode == 2 and message in result.stderr
    assert message in json.loads(result.stdout)["error"]


def test_experiment_predicates_are_checked_before_any_work(images):
    result = _vslsp("experiment", "keep-all-near", "--predicates", images / "syntax.py", "--json")
    assert result.returncode == 2 and "syntax.py, line 3: SyntaxError" in result.stderr
    result = _vslsp("experiment", "house-roof", "--predicates", images / "preds.py")
    assert result.returncode == 2 and "--predicates applies to the VSL-SP experiments" in result.stderr


ICUB = Path(__file__).resolve().parents[1] / "data" / "icub"  # a rendered step: orange pulled, yellow nudged 2.9 px


def test_a_neighbour_nudged_by_a_few_pixels_is_left_out_by_default():
    result = _vslsp("ground", ICUB / "nudged_pre.png", ICUB / "nudged_post.png", "--json")
    assert result.returncode == 0, result.stderr
    data = json.loads(result.stdout)
    assert data["object"]["name"] == "orange" and data["action"] == "pull"
    assert data["nudged"] == [{"name": "yellow", "moved_px": 2.9}]
    text = _vslsp("ground", ICUB / "nudged_pre.png", ICUB / "nudged_post.png")
    assert "left out: yellow moved 2.9 px (less than --min-move 8)" in text.stdout


def test_min_move_0_counts_every_change_and_a_larger_one_leaves_out_more():
    strict = _vslsp("ground", ICUB / "nudged_pre.png", ICUB / "nudged_post.png", "--min-move", "0", "--json")
    assert strict.returncode == 1 and "more than one object moved (yellow left" in json.loads(strict.stdout)["error"]
    # orange moved about 110 px: with a tolerance above every move nothing is left out (both are named)
    all_nudged = _vslsp("ground", ICUB / "nudged_pre.png", ICUB / "nudged_post.png", "--min-move", "500", "--json")
    assert all_nudged.returncode == 1 and "more than one object moved" in json.loads(all_nudged.stdout)["error"]


def test_slip_detection_tells_the_operated_object_from_the_disturbed(tmp_path):
    args = ("ground", ICUB / "nudged_pre.png", ICUB / "nudged_post.png", "--slip-detection", "on")
    result = _vslsp(*args, "--json", "--overlay", tmp_path / "moves.png")
    assert result.returncode == 0, result.stderr
    data = json.loads(result.stdout)
    assert data["object"]["name"] == "orange"
    assert data["moves"]["operated"] == "orange" and data["moves"]["disturbed"] == ["yellow"]
    assert data["moves"]["far"]["yellow"] == {"pre": True, "post": True}
    assert read_image(tmp_path / "moves.png").shape == (480, 1280, 3)
    assert "yellow (disturbed)" in _vslsp(*args).stdout


@pytest.mark.parametrize(
    "args, message",
    [
        (("--min-move", "nan"), "nan is not a number of pixels from 0 up"),
        (("--min-move", "-1"), "-1 is not a number of pixels from 0 up"),
        (("--min-move", "eight"), "'eight' is not a number of pixels"),
        (("--slip-detection", "on", "--predicates", "x.py"), "leave out one of them"),
    ],
)
def test_bad_tolerances_exit_2_before_any_work(images, args, message):
    result = _vslsp("ground", images / "pre.png", images / "post.png", *args, "--json")
    assert result.returncode == 2 and message in json.loads(result.stdout)["error"]
    assert "Traceback" not in result.stderr
