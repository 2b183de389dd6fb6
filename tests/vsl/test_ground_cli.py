"""``vslsp ground PRE POST``: JSON on stdout, the overlay PNG, exit code 2 for bad input."""

import json
import subprocess
import sys

import pytest

from vslsp.vision.image import read_image, write_image
from vslsp.vision.synthetic import Square, tabletop_image


def _vslsp(*args):
    return subprocess.run([sys.executable, "-m", "vslsp", *map(str, args)], capture_output=True, text=True,
                          timeout=60)


@pytest.fixture(scope="module")
def images(tmp_path_factory):
    folder = tmp_path_factory.mktemp("ground")
    still = Square("blue", (500, 420))
    write_image(folder / "pre.png", tabletop_image([Square("purple", (200, 150)), still]))
    write_image(folder / "post.png", tabletop_image([Square("purple", (220, 410)), still]))
    write_image(folder / "small.png", tabletop_image([still], size=(320, 240)))
    write_image(folder / "both.png", tabletop_image([Square("purple", (220, 410)), Square("blue", (480, 130))]))
    (folder / "notes.png").write_text("not an image")
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


@pytest.mark.parametrize("pre, post, message", [
    ("pre.png", "pre.png", "nothing moved"),
    ("pre.png", "small.png", "differ in size"),
    ("pre.png", "missing.png", "cannot read image"),
    ("notes.png", "post.png", "not an image file"),
    ("pre.png", "both.png", "more than one object moved (purple left"),
])
def test_bad_input_exits_2_with_a_message_and_no_traceback(images, pre, post, message):
    result = _vslsp("ground", images / pre, images / post, "--json")
    assert result.returncode == 2
    assert message in result.stderr and "Traceback" not in result.stderr and result.stdout == ""
