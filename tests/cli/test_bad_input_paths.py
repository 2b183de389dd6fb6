"""Paths a user can type: names that are not UTF-8 work everywhere (OpenCV never sees a path),
names the file system cannot hold are refused before any work (issue 27, items 1 and 2)."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest
from helpers.cli import REPO, vslsp, vslsp_process

from vslsp.grounding.synthetic import Square, tabletop_image
from vslsp.vision.image import read_image, write_image

NOT_UTF8 = os.fsdecode(b"\xff")  # the byte 0xff, as Python carries it in a str path (surrogateescape)
LONG = "x" * 300  # one name over the 255 bytes of every common file system
DOMAIN, PROBLEM = REPO / "pddl" / "domain.pddl", REPO / "pddl" / "pull-in-order.pddl"


@pytest.fixture
def pair(tmp_path):
    still = Square("blue", (500, 420))
    pre, post = tmp_path / f"pre{NOT_UTF8}.png", tmp_path / "post.png"
    write_image(pre, tabletop_image([Square("purple", (200, 150)), still]))
    write_image(post, tabletop_image([Square("purple", (220, 410)), still]))
    (tmp_path / f"g{NOT_UTF8}.py").write_text(
        "from vslsp.grounding import predicate\n\n"
        "@predicate('right-half')\ndef right_half(obj, scene):\n    return obj.x > scene.width / 2\n"
    )
    return pre, post


def test_ground_reads_and_writes_paths_that_are_not_utf8(tmp_path, pair):
    pre, post = pair
    overlay = tmp_path / f"o{NOT_UTF8}.png"
    result = vslsp_process(
        "ground", pre, post, "--overlay", overlay, "--predicates", tmp_path / f"g{NOT_UTF8}.py", "--json"
    )
    assert result.returncode == 0, result.stderr
    assert json.loads(result.stdout)["atoms"]["pre"] == ["(far purple)", "(right-half blue)"]
    assert read_image(overlay).shape[1] == 1280


def _run_bytes(*args: object, timeout: float = 600) -> subprocess.CompletedProcess[bytes]:
    """``python -m vslsp ARGS`` in a UTF-8 locale (where Python's stdout is strict), output as bytes."""
    env = {**os.environ, "PYTHONPATH": str(REPO), "LC_ALL": "C.UTF-8"}
    command = [sys.executable, "-m", "vslsp", *(os.fsencode(str(a)) for a in args)]
    return subprocess.run(command, capture_output=True, env=env, timeout=timeout)


def test_scene_writes_into_a_folder_whose_name_is_not_utf8(tmp_path):
    out = tmp_path / f"s{NOT_UTF8}"
    result = _run_bytes("scene", "--out", out, "--width", 64, "--height", 48)
    assert result.returncode == 0, result.stderr
    assert result.stdout.endswith(b"to " + os.fsencode(out) + b"\n")  # printed as the bytes it was given
    assert read_image(out / "head.png").shape == (48, 64, 3) and (out / "scene.json").is_file()


@pytest.mark.slow
@pytest.mark.parametrize("command", [("experiment", "house-roof", "--trials", "1"), ("demo",)], ids=lambda c: c[0])
def test_experiments_and_the_demo_write_reports_into_folders_whose_names_are_not_utf8(tmp_path, command):
    out = tmp_path / f"e{NOT_UTF8}"
    result = _run_bytes(*command, "--out", out, timeout=900)
    assert result.returncode == 0, result.stderr
    assert (out / "report.md").is_file() and any(out.rglob("*.png"))


@pytest.mark.parametrize(
    "command",
    [
        ("scene", "--out", f"out/{LONG}"),
        ("experiment", "house-roof", "--out", f"out/{LONG}"),
        ("teach", "push", "--out", f"out/{LONG}"),
        ("demo", "--out", f"out/{LONG}"),
        ("plan", DOMAIN, PROBLEM, "--out", f"out/{LONG}"),
        ("ground", "pre.png", "post.png", "--overlay", f"out/{LONG}.png"),
    ],
    ids=lambda c: c[0],
)
def test_a_name_over_255_bytes_is_refused_before_any_work(capsys, monkeypatch, tmp_path, command):
    monkeypatch.chdir(tmp_path)
    code, _, err = vslsp(capsys, *command)
    assert code == 2, err
    assert "bytes long" in err and "at most 255 bytes" in err
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())
