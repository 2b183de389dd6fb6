"""``vslsp demo --durative`` (vslsp.loop.durations): the learned domain written with durative actions
lasting the skills' 2τ, and each executed step's duration in the simulator beside the planned one."""

from __future__ import annotations

import json

import pytest
from helpers.cli import vslsp

from vslsp.symbolic.language import check_files


@pytest.mark.slow
def test_the_demo_writes_the_durative_domain_and_compares_durations(capsys, tmp_path):
    out = tmp_path / "out"
    code, _, err = vslsp(capsys, "demo", "--out", out, "--durative")
    assert code == 0, err
    report = json.loads((out / "durations.json").read_text())
    assert [s["object"] for s in report["steps"]] == ["orange", "green", "yellow"]
    assert all(s["planned_s"] == report["durations_s"]["pull"] and s["executed_s"] > 0 for s in report["steps"])
    assert report["planned_makespan_s"] == pytest.approx(3 * report["durations_s"]["pull"], abs=0.01)
    assert "plan's makespan (one arm, in sequence)" in err
    analysis = check_files(str(out / "durative-domain.pddl"), None)
    assert analysis.errors == [] and [d.key for d in analysis.index.of_kind("action")] == ["push", "pull"]
