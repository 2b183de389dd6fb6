"""Input files a user can give: only regular files are read (a FIFO or a device is refused by its
``stat``, never opened), every reader stops at its size limit, and a scene, library or npz that
would exhaust the parser or the memory is refused first (issue 27, items 2 and 3)."""

from __future__ import annotations

import io
import os
import shutil
import stat
import zipfile

import pytest
from helpers.cli import REPO, vslsp, vslsp_process
from numpy.lib import format as npy

from vslsp.skills import default_library_path
from vslsp.symbolic.validation.validate import MAX_PLAN_BYTES

DOMAIN, PROBLEM = REPO / "pddl" / "domain.pddl", REPO / "pddl" / "pull-in-order.pddl"


@pytest.fixture
def fifo(tmp_path):
    path = tmp_path / "fifo"
    os.mkfifo(path)
    return path


def _library(tmp_path, **replaced):
    """A copy of the shipped library with files replaced in place (vslsp refuses a library's links):
    name -> bytes, "fifo" or "/dev/zero" (a character device made there; root only)."""
    folder = tmp_path / "lib"
    shutil.copytree(default_library_path(), folder)
    for name, content in replaced.items():
        (folder / name).unlink()
        if isinstance(content, bytes):
            (folder / name).write_bytes(content)
        elif content == "fifo":
            os.mkfifo(folder / name)
        else:
            try:
                os.mknod(folder / name, 0o666 | stat.S_IFCHR, os.makedev(1, 5))  # what /dev/zero is
            except PermissionError:
                pytest.skip("making a device needs root")
    return folder


# Each command with the input that is a FIFO (or a device) put in the place "{}".
READERS = [
    ("pddl", "check", "{}"),
    ("plan", "{}", PROBLEM),
    ("plan", DOMAIN, "{}"),
    ("validate", DOMAIN, PROBLEM, "{}"),
    ("scene", "--scene", "{}"),
    ("ground", "{}", "{}"),
    ("ground", "{}", "{}", "--predicates", "{}.py"),
]


@pytest.mark.parametrize("command", READERS, ids=lambda c: " ".join(map(str, c[:2])))
@pytest.mark.parametrize("special", ["fifo", "/dev/zero"])
def test_a_fifo_or_a_device_is_refused_by_its_stat_never_read(tmp_path, fifo, command, special):
    target = str(fifo) if special == "fifo" else special
    if command[-1] == "{}.py":
        (tmp_path / "predicates.py").unlink(missing_ok=True)
        os.mkfifo(tmp_path / "predicates.py")
        command = (*command[:-1], tmp_path / "predicates.py")
    args = [target if a == "{}" else a for a in command]
    if command[0] == "scene":
        args += ["--out", tmp_path / "views"]
    result = vslsp_process(*args, cwd=tmp_path, timeout=120)
    assert result.returncode == 2, result.stderr
    assert "not a regular file" in result.stderr and "Traceback" not in result.stderr


@pytest.mark.parametrize("place", ["library.json", "push_reach.npz", "push_demos.npz"])
@pytest.mark.parametrize("special", ["fifo", "/dev/zero"])
def test_a_skill_library_file_that_is_a_fifo_or_a_device_is_refused(capsys, tmp_path, place, special):
    folder = _library(tmp_path, **{place: special})
    code, _, err = vslsp(capsys, "demo", "--skills", folder, "--out", tmp_path / "out")
    assert code == 2 and "not a regular file" in err, err


def test_shell_load_of_a_device_or_a_fifo_is_refused(tmp_path, fifo):
    result = vslsp_process("shell", input=f"load /dev/zero\nload {fifo}\nquit\n", timeout=60)
    assert (
        result.returncode == 1  # a piped session with refused commands (--keep-going: 0)
        and result.stderr.count("not a regular file") + result.stdout.count("not a regular file") == 2
    ), result.stdout + result.stderr


@pytest.mark.parametrize("reach", [b"root:x:0:0:root:/root:/bin/bash\n", "/dev/zero"], ids=["passwd", "zero"])
def test_a_reach_file_that_is_text_or_a_device_is_named_as_such_not_as_a_pickle(capsys, tmp_path, reach):
    code, _, err = vslsp(
        capsys, "demo", "--skills", _library(tmp_path, **{"push_reach.npz": reach}), "--out", tmp_path / "out"
    )
    assert code == 2 and "pickle" not in err, err
    assert "not an .npz file" in err or "not a regular file" in err


def _declared_npz(**shapes: tuple[int, ...]) -> bytes:
    """An npz whose members declare ``shapes`` of float64 and hold no data: a few hundred bytes."""
    data = io.BytesIO()
    with zipfile.ZipFile(data, "w") as archive:
        for name, shape in shapes.items():
            header = io.BytesIO()
            npy.write_array_header_1_0(header, {"descr": "<f8", "fortran_order": False, "shape": shape})
            archive.writestr(f"{name}.npy", header.getvalue())
    return data.getvalue()


@pytest.mark.parametrize(
    "place, arrays",
    [
        ("push_reach.npz", {"meta": (), "weights": (10**6, 10**6)}),  # 8 TB declared in 584 bytes
        ("push_demos.npz", {"t_0": (175_000_000,), "y_0": (175_000_000, 3)}),  # 4.2 GB of demonstrations
    ],
)
def test_an_npz_declaring_a_huge_array_is_refused_on_its_header(capsys, tmp_path, place, arrays):
    content = _declared_npz(**arrays)
    assert len(content) < 1000
    code, _, err = vslsp(capsys, "demo", "--skills", _library(tmp_path, **{place: content}), "--out", tmp_path / "out")
    assert code == 2 and "nothing was loaded" in err and place in err, err


@pytest.mark.parametrize(
    "content, message",
    [
        ("[" * 100_000, "nests deeper than 64 levels"),
        ('{"cubes": [{"name": "red", "colour": "red", "x": 1' + "0" * 400 + "}]}", "an integer of 401 digits"),
        ('{"cubes": [{"name": "red", "colour": "red", "x": 1' + "0" * 5000 + "}]}", "an integer of 5001 digits"),
        ('{"cubes": [], "pad": "' + "x" * 200_000 + '"}', "larger than 100 kB"),
    ],
    ids=["nested", "401-digits", "5001-digits", "too-large"],
)
def test_a_scene_file_that_would_exhaust_the_parser_is_refused(capsys, tmp_path, content, message):
    scene = tmp_path / "scene.json"
    scene.write_text(content)
    code, _, err = vslsp(capsys, "scene", "--scene", scene, "--out", tmp_path / "views")
    assert code == 2 and message in err, err
    assert not (tmp_path / "views" / "head.png").exists()


def test_a_library_index_over_its_limit_is_refused_while_reading(capsys, tmp_path):
    folder = _library(tmp_path, **{"library.json": b'{"pad": "' + b"x" * 2_000_000 + b'"}'})
    code, _, err = vslsp(capsys, "demo", "--skills", folder, "--out", tmp_path / "out")
    assert code == 2 and "library.json" in err and "larger than 1 MB" in err, err


def test_a_plan_file_over_its_limit_is_refused(capsys, tmp_path):
    plan = tmp_path / "plan.txt"
    plan.write_text("(pull orange)\n" * (MAX_PLAN_BYTES // 14 + 1))
    code, _, err = vslsp(capsys, "validate", DOMAIN, PROBLEM, plan)
    assert code == 2 and "larger than 1 MB" in err, err
