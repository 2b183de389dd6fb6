"""Ctrl-C during ``vslsp vsl reproduce`` and ``vslsp vsl3d reproduce --step`` on a real learned
recording (docs/bad-input.md, "Signals and crashes"): the command ends with 130 and one line, no
traceback, and its session file is the one before the run (never half written), with no
temporary file beside it.

The program waits at a marked point of the real run (the answer computed, or the session file
half written through :func:`vslsp.outputs.atomic_file`) for the test's signal."""

from __future__ import annotations

import json
import signal
import subprocess
import sys

import pytest
from helpers.cli import vslsp
from helpers.events import became_true, experiment_program
from helpers.processes import command

from vslsp.experiments.cloud_folders import write_cloud_recording
from vslsp.experiments.picture_folders import write_recording
from vslsp.vsl.learned import save_learned
from vslsp.vsl.recordings import learn, read_recording

pytestmark = pytest.mark.slow

#: Marks ``answered`` once ``MODULE.next_operation`` has answered, then waits.
AFTER_THE_ANSWER = """
import os, pathlib, time
import {module} as learned
real = learned.next_operation
def waiting(*args, **kwargs):
    answer = real(*args, **kwargs)
    (pathlib.Path(os.environ['VSLSP_TEST_MARKERS']) / 'answered').write_text('')
    time.sleep(120)
    return answer
learned.next_operation = waiting
"""

#: Writes half of the session file through the real atomic_file, marks ``writing``, then waits.
WHILE_WRITING = """
import os, pathlib, time
import vslsp.vsl.learned as learned
from vslsp.outputs import atomic_file
def writing(path, text):
    with atomic_file(path, "w") as stream:
        stream.write(text[: len(text) // 2])
        stream.flush()
        (pathlib.Path(os.environ['VSLSP_TEST_MARKERS']) / 'writing').write_text('')
        time.sleep(120)
        stream.write(text[len(text) // 2 :])
learned.write_text = writing
"""


def interrupted(args: list[object], tmp_path, setup: str, marker: str) -> tuple[int, str, str]:
    """Run ``vslsp ARGS`` after ``setup``, send it SIGINT once ``marker`` is written, and return
    its exit code, stdout and stderr."""
    line, env = command(args, tmp_path)
    line = [sys.executable, "-c", experiment_program(setup), *line[3:]]
    process = subprocess.Popen(line, env=env, text=True, cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        assert became_true(lambda: (tmp_path / "markers" / marker).exists(), process)
        process.send_signal(signal.SIGINT)
        stdout, stderr = process.communicate(timeout=120)
    finally:
        process.kill()
    return process.returncode, stdout, stderr


def check_left_as_before(code: int, stdout: str, stderr: str, session, before: bytes) -> None:
    assert code == 130, stderr
    assert "Traceback" not in stderr and len(stderr.strip().splitlines()) == 1, stderr
    assert "error" in json.loads(stdout)  # --json prints JSON, even when interrupted
    assert session.read_bytes() == before
    assert sorted(p.name for p in session.parent.iterdir()) == [session.name]  # no temporary file


@pytest.fixture(scope="module")
def pictures(tmp_path_factory):
    """alphabet-ordering (seed 0) photographed into a folder and learned into DEMO."""
    folder, demo = tmp_path_factory.mktemp("recording"), tmp_path_factory.mktemp("demo")
    write_recording("alphabet-ordering", 0, folder)
    recording = read_recording(folder)
    save_learned(learn(recording), recording, demo)
    return folder, demo


def started_session(capsys, tmp_path, *args) -> tuple[object, bytes]:
    """A session file after its first operation's answer."""
    session = tmp_path / "session" / "session.json"
    code, _, err = vslsp(capsys, *args, "--step", session, "--json")
    assert code == 0, err
    return session, session.read_bytes()


@pytest.mark.parametrize(("setup", "marker"), [(AFTER_THE_ANSWER, "answered"), (WHILE_WRITING, "writing")])
def test_ctrl_c_during_vsl_reproduce_leaves_the_session_as_it_was(pictures, tmp_path, capsys, setup, marker):
    folder, demo = pictures
    session, before = started_session(capsys, tmp_path, "vsl", "reproduce", demo, folder / "01-pre.png")
    args = ["vsl", "reproduce", demo, folder / "01-post.png", "--step", session, "--json"]
    code, stdout, stderr = interrupted(args, tmp_path, setup.format(module="vslsp.vsl.learned"), marker)
    check_left_as_before(code, stdout, stderr, session, before)
    assert json.loads(before)["next"] == 1


def test_ctrl_c_during_vsl3d_reproduce_leaves_the_session_as_it_was(tmp_path, capsys):
    folder = tmp_path / "clouds"
    folder.mkdir()
    write_cloud_recording(0, folder, ("ply",))
    assert vslsp(capsys, "vsl3d", "learn", folder, "--out", tmp_path / "demo")[0] == 0
    session, before = started_session(capsys, tmp_path, "vsl3d", "reproduce", tmp_path / "demo", folder / "01-pre.ply")
    args = ["vsl3d", "reproduce", tmp_path / "demo", folder / "01-post.ply", "--step", session, "--json"]
    setup = AFTER_THE_ANSWER.format(module="vslsp.vsl3d.learned")
    code, stdout, stderr = interrupted(args, tmp_path, setup, "answered")
    check_left_as_before(code, stdout, stderr, session, before)
