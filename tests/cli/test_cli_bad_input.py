"""Bad input to scene, teach and demo: exit 2 before any work, one line naming the input, no
traceback (docs/bad-input.md lists every class and what each command answers)."""

from __future__ import annotations

import json
import re
import shutil

import pytest
from helpers.cli import checkout_copy, tree_digest, unwritable_folder, vslsp, vslsp_process

from vslsp.skills import default_library_path

# Commands that share an edge: a seed, a report folder (option --out). The command comes first,
# the options after it; each would run for seconds to minutes, so exit 2 proves the check came first.
SEEDED = [("scene",), ("teach", "push"), ("demo",)]
WRITING = [("scene",), ("teach", "push"), ("demo",)]


@pytest.mark.parametrize("command", SEEDED, ids=" ".join)
@pytest.mark.parametrize("seed", ["-1", "-123456", "4294967296", "one"])
def test_a_bad_seed_is_refused_up_front(capsys, monkeypatch, tmp_path, command, seed):
    monkeypatch.chdir(tmp_path)  # no default output folder appears in the checkout
    code, out, err = vslsp(capsys, *command, "--seed", seed)
    assert code == 2 and out == ""
    assert "Invalid value for '--seed'" in err and "a seed is an integer from 0 to 4294967295" in err


@pytest.mark.parametrize("command", WRITING, ids=" ".join)
def test_an_output_folder_under_a_file_is_refused_up_front(capsys, tmp_path, command):
    (tmp_path / "plain").write_text("not a folder")
    code, _, err = vslsp(capsys, *command, "--out", tmp_path / "plain" / "report")
    assert code == 2 and f"{tmp_path / 'plain'} is a file" in err
    assert (tmp_path / "plain").read_text() == "not a folder"


@pytest.mark.parametrize("command", WRITING, ids=" ".join)
def test_an_unwritable_output_folder_is_refused_up_front(capsys, tmp_path, command):
    folder = unwritable_folder(tmp_path) / "report"
    code, _, err = vslsp(capsys, *command, "--out", folder)
    assert code == 2 and f"cannot write into the folder {folder}" in err


@pytest.mark.parametrize("command", WRITING, ids=" ".join)
def test_no_traceback_as_a_process(tmp_path, command):
    """The same edge through a real process: stderr holds the message only."""
    (tmp_path / "plain").write_text("x")
    result = vslsp_process(*command, "--seed", "-1", cwd=tmp_path)
    assert result.returncode == 2 and "Traceback" not in result.stderr and "--seed" in result.stderr
    result = vslsp_process(*command, "--out", tmp_path / "plain" / "x", cwd=tmp_path)
    assert result.returncode == 2 and "Traceback" not in result.stderr and "is a file" in result.stderr


# -- sizes and counts ----------------------------------------------------------------------------
@pytest.mark.parametrize(
    "args",
    [
        ("scene", "--width", "0"),
        ("scene", "--width", "-5"),
        ("scene", "--height", "0"),
        ("scene", "--width", "100000"),
        ("scene", "--cubes", "0"),
        ("teach", "push", "--demos", "0"),
        ("teach", "push", "--demos", "-2"),
    ],
    ids=" ".join,
)
def test_sizes_and_counts_must_be_positive(capsys, monkeypatch, tmp_path, args):
    monkeypatch.chdir(tmp_path)
    code, out, err = vslsp(capsys, *args)
    assert code == 2 and out == "" and "is not in the range" in err


# -- scene files ---------------------------------------------------------------------------------
GOOD_CUBE = {"name": "red", "colour": "red", "x": 0.25, "y": -0.05, "yaw": 0.0}


@pytest.mark.parametrize(
    ("cube", "landmark", "expected"),
    [
        ({"x": float("nan")}, {}, r"cubes\[0\]\.x is nan: not a finite number"),
        ({"y": float("inf")}, {}, r"cubes\[0\]\.y is inf: not a finite number"),
        ({"yaw": float("nan")}, {}, r"cubes\[0\]\.yaw is nan"),
        ({"x": 2.0}, {}, r"cubes\[0\]\.x is 2\.0 m: the cube 'red' would be off the table"),
        ({"y": -0.9}, {}, r"cubes\[0\]\.y is -0\.9 m: the cube 'red' would be off the table"),
        ({"x": "0.25"}, {}, r"cubes\[0\]\.x is '0\.25', not a number"),
        ({"x": True}, {}, r"cubes\[0\]\.x is True, not a number"),
        ({"size": 3.0}, {}, r"cubes\[0\]\.size is 3\.0 m; use 0\.02-0\.1 m"),
        ({"name": 5}, {}, r"cubes\[0\]\.name is 5, not a name"),
        ({}, {"x": float("nan")}, r"landmark\.x is nan: not a finite number"),
        ({}, {"x": 5.0}, r"landmark\.x is 5\.0 m: the line would be off the table"),
        ({}, {"angle": float("inf")}, r"landmark\.angle is inf"),
    ],
)
def test_a_scene_file_names_the_bad_field(capsys, tmp_path, cube, landmark, expected):
    scene = tmp_path / "scene.json"
    scene.write_text(json.dumps({"cubes": [{**GOOD_CUBE, **cube}], "landmark": {"x": 0.225, "angle": 0.0, **landmark}}))
    code, _, err = vslsp(capsys, "scene", "--scene", scene, "--out", tmp_path / "views")
    assert code == 2
    assert err.startswith(f"error: scene file {scene}: ")
    assert re.search(expected, err), err
    assert not (tmp_path / "views" / "head.png").exists()


@pytest.mark.parametrize(
    ("content", "expected"),
    [
        (b"\xff\xfe{}", "not UTF-8 text"),
        (b'{"cubes": {"red": 1}}', "not a scene description"),
        (b"[1, 2]", "not a scene description"),
        (b'{"cubes": [1]}', r"cubes\[0\] is 1, not an object"),
        (b'{"cubes": [], "landmark": [0.2]}', r"landmark is \[0\.2\], not an object"),
    ],
)
def test_a_malformed_scene_file_is_an_input_error(capsys, tmp_path, content, expected):
    scene = tmp_path / "scene.json"
    scene.write_bytes(content)
    code, _, err = vslsp(capsys, "scene", "--scene", scene, "--out", tmp_path / "views")
    assert code == 2 and re.search(expected, err), err


# -- teach: the shipped library is written only on request -------------------------------------
@pytest.mark.parametrize("where", ["shipped skills", "shipped pddl", "package", "source tree"])
def test_teach_refuses_vslsp_own_folders_without_force(tmp_path, where):
    # On a copy of the checkout (the command runs from it), so that a regression writes there,
    # never into the real source tree.
    checkout = checkout_copy(tmp_path / "checkout")
    folder = {
        "shipped skills": checkout / "skills",
        "shipped pddl": checkout / "pddl",
        "package": checkout / "vslsp" / "skills",
        "source tree": checkout,
    }[where]
    before = tree_digest(checkout)
    done = vslsp_process("teach", "push", "--out", folder, cwd=tmp_path, checkout=checkout, timeout=120)
    assert done.returncode == 2 and done.stdout == "", done.stderr
    assert f"--out: {folder} is" in done.stderr and "only with --force" in done.stderr
    assert "Traceback" not in done.stderr
    assert tree_digest(checkout) == before and not (tmp_path / "out").exists()


def test_teach_refuses_a_damaged_library_without_force(capsys, tmp_path):
    library = tmp_path / "skills"
    shutil.copytree(default_library_path(), library)
    (library / "push_reach.npz").write_bytes(b"garbage")
    code, _, err = vslsp(capsys, "teach", "push", "--out", library)
    assert code == 2 and "holds a damaged skill library" in err
    assert f"`vslsp teach push --out {library} --force`" in err


# -- demo: the library is checked before the simulation ------------------------------------------
def test_demo_without_a_skill_is_refused_up_front(capsys, tmp_path):
    library = tmp_path / "skills"
    shutil.copytree(default_library_path(), library)
    index = json.loads((library / "library.json").read_text())
    del index["skills"]["pull"]
    (library / "library.json").write_text(json.dumps(index))
    code, out, err = vslsp(capsys, "demo", "--skills", library, "--out", tmp_path / "report")
    assert code == 2 and out == ""
    assert "has no 'pull' skill" in err and f"vslsp teach pull --out {library}" in err
    assert not (tmp_path / "report" / "report.md").exists()


def test_demo_with_tau_0_is_refused_up_front(capsys, tmp_path):
    import numpy as np

    library = tmp_path / "skills"
    shutil.copytree(default_library_path(), library)
    arrays = dict(np.load(library / "pull_reach.npz"))
    meta = json.loads(str(arrays["meta"]))
    arrays["meta"] = np.array(json.dumps({**meta, "tau": 0.0}))
    np.savez(library / "pull_reach.npz", **arrays)
    code, _, err = vslsp(capsys, "demo", "--skills", library, "--out", tmp_path / "report")
    assert code == 2 and "pull_reach.npz: tau is 0, outside (0, 60]" in err


def test_demo_with_a_missing_library_says_how_to_make_one(capsys, tmp_path):
    code, _, err = vslsp(capsys, "demo", "--skills", tmp_path / "none", "--out", tmp_path / "report")
    assert code == 2 and f"no skill library in {tmp_path / 'none'}" in err
    assert f"vslsp teach push --out {tmp_path / 'none'}" in err
