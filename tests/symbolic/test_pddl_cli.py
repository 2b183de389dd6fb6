"""``vslsp pddl check``, ``vslsp plan`` and ``vslsp validate``: JSON on stdout, exit codes
0 (done), 1 (no plan / invalid plan), 2 (malformed input, FILE:LINE:COL on stderr)."""

import json
import subprocess
import sys

import pytest

from conftest import PDDL
from vslsp.cli import main

DOMAIN = PDDL / "domain.pddl"


def vslsp(capsys, *args) -> tuple[int, str, str]:
    """Run the CLI in-process (the planner is a real subprocess of Fast Downward)."""
    with pytest.raises(SystemExit) as done:
        main([str(a) for a in args])
    out, err = capsys.readouterr()
    return done.value.code, out, err


def test_plan_json_keeps_the_order_and_validates(capsys, tmp_path):
    code, out, _ = vslsp(capsys, "plan", DOMAIN, PDDL / "pull-in-order.pddl", "--json", "--out", tmp_path / "plan")
    data = json.loads(out)
    assert code == 0 and data["plan"] == ["pull orange", "pull green", "pull yellow"]
    assert data["planner"] == "fast-downward" and isinstance(data["time_s"], float)
    code, out, _ = vslsp(capsys, "validate", DOMAIN, PDDL / "pull-in-order.pddl", tmp_path / "plan", "--json")
    assert code == 0 and json.loads(out)["valid"] is True


def test_validate_rejects_the_wrong_order_with_exit_1(capsys, tmp_path):
    plan = tmp_path / "plan"
    plan.write_text("(pull green)\n(pull orange)\n(pull yellow)\n")
    code, out, _ = vslsp(capsys, "validate", DOMAIN, PDDL / "pull-in-order.pddl", plan, "--json")
    verdict = json.loads(out)
    assert code == 1 and verdict["valid"] is False and "sometime-before" in verdict["reason"]
    code, out, err = vslsp(capsys, "validate", DOMAIN, PDDL / "pull-in-order.pddl", plan)
    assert code == 1 and out.startswith("invalid: constraint (sometime-before")
    assert err.startswith("error: invalid plan: constraint (sometime-before")


def test_unsolvable_problem_is_no_plan_exit_1(capsys, tmp_path):
    problem = tmp_path / "unsolvable.pddl"
    problem.write_text((PDDL / "keep-all-near.pddl").read_text().replace(
        "(not (far ?b)))))", "(not (far ?b))))\n  (:constraints (always (far green))))"))
    code, out, err = vslsp(capsys, "plan", DOMAIN, problem, "--json")
    assert code == 1 and out == "" and err.startswith("error: no plan: ")


def test_malformed_input_exit_2_with_file_line_column(capsys, tmp_path):
    problem = tmp_path / "typo.pddl"
    problem.write_text((PDDL / "simple-push-pull.pddl").read_text().replace("(far red)\n", "(far red\n"))
    code, _, err = vslsp(capsys, "pddl", "check", DOMAIN, problem)
    assert code == 2 and err.startswith(f"error: {problem}:") and "')' is missing" in err
    code, _, err = vslsp(capsys, "plan", DOMAIN, problem)
    assert code == 2 and "Traceback" not in err
    bad_plan = tmp_path / "plan"
    bad_plan.write_text("(pull orange)\n(fly green)\n")
    code, _, err = vslsp(capsys, "validate", DOMAIN, PDDL / "pull-in-order.pddl", bad_plan)
    assert code == 2 and err.startswith(f"error: {bad_plan}:2:2: unknown action 'fly'")


def test_pddl_check_summarises(capsys):
    code, out, _ = vslsp(capsys, "pddl", "check", DOMAIN, PDDL / "pull-in-order.pddl", "--json")
    data = json.loads(out)
    assert code == 0 and data["domain"]["actions"] == ["push", "pull"]
    assert data["problem"]["constraints"][0] == "(sometime-before (not (far green)) (not (far orange)))"


def test_plan_runs_as_a_program():
    result = subprocess.run([sys.executable, "-m", "vslsp", "plan", str(DOMAIN), str(PDDL / "simple-push-pull.pddl")],
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    assert result.stdout.splitlines() == ["1. pull red", "2. push green"]
