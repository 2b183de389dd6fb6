"""``--json`` on every exit path: whatever happens (done, bad input: 2, a planner failing inside:
3), stdout holds exactly one JSON object and its ``exit_code`` is the command's exit code
(docs/cli.md). Interrupted runs: tests/tasks/test_framework.py and test_ray_backend.py."""

from __future__ import annotations

import json
import stat

import pytest
from helpers.cli import vslsp, vslsp_process
from helpers.symbolic import PDDL

DOMAIN = PDDL / "domain.pddl"
PROBLEM = PDDL / "pull-in-order.pddl"


def one_object(out: str) -> dict:
    """stdout parsed as one JSON object (json.loads refuses anything before or after it)."""
    data = json.loads(out)
    assert isinstance(data, dict)
    return data


def test_plan_exits_3_with_json_when_fast_downward_fails_inside(capsys, monkeypatch, tmp_path):
    # A Fast Downward whose driver dies with a critical error (exit 35): an internal failure,
    # neither bad input nor "no plan".
    crashing = tmp_path / "fast-downward.py"
    crashing.write_text("import sys\nprint('search: critical error: out of ideas')\nsys.exit(35)\n")
    crashing.chmod(crashing.stat().st_mode | stat.S_IXUSR)
    monkeypatch.setattr("vslsp.symbolic.engines.fast_downward.driver", lambda: crashing)
    code, out, err = vslsp(capsys, "plan", DOMAIN, PROBLEM, "--json", "--out", tmp_path / "plan.txt")
    data = one_object(out)
    assert code == 3 and data["exit_code"] == 3
    assert "Fast Downward" in data["error"] and "critical error: out of ideas" in data["error"]  # its own words
    assert "Traceback" not in err and not (tmp_path / "plan.txt").exists()


@pytest.mark.parametrize(
    "make",
    [
        pytest.param(lambda folder: (folder / "domain.pddl", "(define (domain d) (:action a"), id="unclosed domain"),
        pytest.param(lambda folder: (folder / "domain.pddl", "(define (problem p))"), id="a problem as domain"),
    ],
)
def test_pddl_check_and_validate_exit_2_with_json_on_a_malformed_domain(capsys, tmp_path, make):
    path, text = make(tmp_path)
    path.write_text(text)
    plan = tmp_path / "plan.txt"
    plan.write_text("(pull orange)\n")
    for command in (["pddl", "check", path, PROBLEM], ["validate", path, PROBLEM, plan]):
        code, out, err = vslsp(capsys, *command, "--json")
        data = one_object(out)
        assert code == 2 and data["exit_code"] == 2, (command, out)
        assert "Traceback" not in err


def test_validate_exits_2_with_json_on_a_malformed_plan(capsys, tmp_path):
    plan = tmp_path / "plan.txt"
    plan.write_text("(pull orange)\n(fly green)\n")
    code, out, err = vslsp(capsys, "validate", DOMAIN, PROBLEM, plan, "--json")
    data = one_object(out)
    assert code == 2 and data["exit_code"] == 2 and "unknown action 'fly'" in data["error"]
    assert "Traceback" not in err


@pytest.mark.parametrize(
    "arguments",
    [
        ["table-cleaning", "--method", "magic"],
        ["table-cleaning", "--trials", "0"],
        ["table-cleaning", "--faults"],
        ["table-cleaning", "--workers", "-1"],
        ["stacking-in-the-dark"],
    ],
    ids=" ".join,
)
def test_vsl3d_errors_are_one_json_object_with_exit_2(capsys, tmp_path, arguments):
    code, out, err = vslsp(capsys, "vsl3d", *arguments, "--json", "--out", tmp_path / "report")
    data = one_object(out)
    assert code == 2 and data["exit_code"] == 2 and data["error"], out
    assert "Traceback" not in err and not (tmp_path / "report" / "report.json").exists()


def test_json_errors_as_a_program_are_one_object_on_stdout(tmp_path):
    # As a user's script sees it: the installed entry point's streams, not this process's capture
    done = vslsp_process("vsl3d", "table-cleaning", "--method", "magic", "--json", "--out", tmp_path, timeout=120)
    assert done.returncode == 2 and one_object(done.stdout)["exit_code"] == 2
    assert "Traceback" not in done.stderr and done.stderr.strip()
