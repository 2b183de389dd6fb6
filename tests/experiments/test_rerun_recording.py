"""``--rerun FILE.rrd`` on real trials: a pull-in-order trial's images, plan and symbolic state on
one timeline, a table-cleaning trial's point clouds, read back with the SDK; and the bad input
that is refused before any work."""

from __future__ import annotations

import subprocess
import sys

import pytest
from helpers.cli import vslsp

pytest.importorskip("rerun.chunk")

from helpers.rerun import rows  # noqa: E402 (once the SDK is known to be there)


@pytest.mark.slow
def test_a_pull_in_order_trial_is_recorded_with_images_plan_and_state_on_one_timeline(tmp_path, capsys):
    out = tmp_path / "run.rrd"
    code, _, _ = vslsp(capsys, "experiment", "pull-in-order", "--seed", 3, "--out", tmp_path / "r", "--rerun", out)
    assert code == 0
    logged = rows(out)
    assert not (tmp_path / "run.rrd.parts").exists()
    for entity in ("camera/before", "camera/after", "plan", "state", "narration", "arm", "hand_path"):
        assert logged.get(f"/trial/3/{entity}"), entity
        assert all("step" in row and "sim_time" in row for row in logged[f"/trial/3/{entity}"])
    (plan, *_) = logged["/trial/3/plan"]
    assert plan["TextDocument:text"] == ["1. pull orange\n2. pull green\n3. pull yellow"]
    states = [row["TextDocument:text"][0] for row in logged["/trial/3/state"]]
    assert sorted(states[-1].splitlines()) == ["(not (far green))", "(not (far orange))", "(not (far yellow))"]
    steps = [row["step"] for row in logged["/trial/3/camera/after"]]
    assert steps == sorted(steps) and plan["step"] > steps[0]


@pytest.mark.slow
def test_a_table_cleaning_trial_is_recorded_with_its_point_clouds(tmp_path, capsys):
    out = tmp_path / "clean.rrd"
    vslsp(capsys, "experiment", "table-cleaning", "--seed", 0, "--out", tmp_path / "r", "--rerun", out)
    clouds = rows(out)["/trial/0/cloud/capture"]
    assert clouds and all(len(row["Points3D:positions"]) > 100 for row in clouds)


@pytest.mark.parametrize(
    ("args", "said"),
    [
        (("experiment", "house-roof", "--rerun", "x.rrd"), "--rerun applies to the VSL-3D and VSL-SP experiments"),
        (("experiment", "pull-in-order", "--rerun", "x.txt"), "is not a rerun recording's name"),
        (("demo", "--rerun", "nowhere/x.rrd"), "does not exist"),
    ],
)
def test_bad_rerun_input_is_refused_before_any_work(tmp_path, capsys, monkeypatch, args, said):
    monkeypatch.chdir(tmp_path)
    code, _, err = vslsp(capsys, *args, "--out", tmp_path / "r")
    assert code == 2 and said in err and not (tmp_path / "r" / "report.json").exists()


def test_rerun_without_the_sdk_names_the_extra(tmp_path):
    blocked = "import sys; sys.modules['rerun'] = None; from vslsp.cli import main; main(sys.argv[1:])"
    done = subprocess.run(
        [sys.executable, "-c", blocked, "demo", "--out", tmp_path / "r", "--rerun", tmp_path / "x.rrd"],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 2 and "pip install 'vslsp[rerun]'" in done.stderr
    assert len(done.stderr.strip().splitlines()) == 1
