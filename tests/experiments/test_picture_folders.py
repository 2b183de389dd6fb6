"""The closed loop of VSL from picture files (docs/recordings.md), as a user with a camera and
a robot runs it: the Tower of Hanoi (seven operations, stacking) demonstrated and photographed
into a recording folder, learned with ``vslsp vsl learn``; in a new scene the test photographs
the world, asks ``vslsp vsl reproduce --step``, executes the answer with the Panda's
pick-and-place skill, and photographs again until the answer is done. Judged on the ground
truth: every operation within 1 cm and 5 deg of its demonstrated relation."""

import json

import pytest
from helpers.cli import vslsp

from vslsp.experiments.picture_folders import closed_loop, write_recording

pytestmark = pytest.mark.slow


def test_the_closed_loop_reproduces_seven_operations_from_picture_files_alone(tmp_path, capsys):
    goal = write_recording("tower-of-hanoi", 0, tmp_path / "recording")
    code, _, err = vslsp(capsys, "vsl", "learn", tmp_path / "recording", "--out", tmp_path / "demo")
    assert code == 0, err
    (tmp_path / "scenes").mkdir()

    def ask(scene):
        code, out, err = vslsp(
            capsys, "vsl", "reproduce", tmp_path / "demo", scene, "--step", tmp_path / "s.json", "--json"
        )
        assert code == 0, err
        return json.loads(out)

    *operations, final = closed_loop("tower-of-hanoi", 0, goal, tmp_path / "scenes", ask)
    assert [op["operation"] for op in operations] == list(range(1, 8))
    for op in operations + final["final"]:
        assert op["position_error_m"] <= 0.01 and op["angle_error_deg"] <= 5.0 and op["level_error_m"] <= 0.008, op
    assert ask(tmp_path / "scenes" / "scene-08.png") == {"done": True, "operations": 7}  # and it stays done
