"""Every planner run is bounded (docs/bad-input.md, "The planner's limits"): a default time and
memory limit, ``plan --timeout / --memory`` to change them, reaching one an exit 1 that names it;
Fast Downward in the command's process group, ended with its folder on every way out; its
failures name the component and its last line."""

from __future__ import annotations

import json
import shutil
import signal

import pytest
from helpers.cli import REPO, vslsp
from helpers.events import became_true, process_gone, wait_until
from helpers.processes import planner_processes, start

from vslsp.symbolic.engines.fast_downward import failure
from vslsp.symbolic.engines.fast_downward import run as run_fast_downward
from vslsp.symbolic.engines.outcomes import PlanStatus
from vslsp.symbolic.engines.planner import DEFAULT_MEMORY_MB, DEFAULT_TIMEOUT_S, DIRECT

DOMAIN = REPO / "pddl" / "domain.pddl"
SOLVABLE = REPO / "pddl" / "pull-in-order.pddl"
FORALL = REPO / "tests" / "data" / "limits" / "forall-or.pddl"  # Fast Downward's translator grows without end


@pytest.mark.parametrize("value", ["nan", "inf", "-inf", "1e300", "0", "-1", "x"])
def test_a_timeout_that_is_no_time_limit_is_refused(capsys, value):
    code, out, err = vslsp(capsys, "plan", DOMAIN, SOLVABLE, "--timeout", value, "--json")
    assert code == 2 and "--timeout" in err and "Traceback" not in err
    assert json.loads(out)["exit_code"] == 2


@pytest.mark.parametrize("value", ["0", "-5", "63", "2e9", "lots"])
def test_a_memory_limit_out_of_range_is_refused(capsys, value):
    code, _, err = vslsp(capsys, "plan", DOMAIN, SOLVABLE, "--memory", value)
    assert code == 2 and "--memory" in err


def test_the_defaults_are_stated_and_a_plan_is_unaffected(capsys):
    code, out, err = vslsp(capsys, "plan", "--help")
    assert f"{DEFAULT_TIMEOUT_S:g}" in out.replace("300.0", "300") and str(DEFAULT_MEMORY_MB) in out
    code, out, err = vslsp(capsys, "plan", DOMAIN, SOLVABLE, "--json")
    assert code == 0 and json.loads(out)["plan"]


def test_reaching_the_time_limit_is_exit_1_naming_it(capsys):
    code, out, err = vslsp(capsys, "plan", DOMAIN, FORALL, "--timeout", "1", "--memory", "700", "--json")
    data = json.loads(out)
    assert code == 1 and "time limit of 1 s reached" in data["error"]
    assert data["status"] == "timeout"  # the planner's status, typed: not "unsolvable_proven"
    assert "Fast Downward failed" not in err


# fast-downward and -lama: the driver run directly; fast-downward-opt: through unified-planning's engine.
@pytest.mark.parametrize("planner", ["fast-downward", "fast-downward-lama", "fast-downward-opt"])
def test_reaching_the_memory_limit_is_exit_1_naming_it(capsys, planner):
    code, out, err = vslsp(capsys, "plan", DOMAIN, FORALL, "--memory", "300", "--planner", planner)
    assert code == 1 and "memory limit of 300 MB reached" in err and "--memory" in err


@pytest.mark.slow
def test_the_forall_reproducer_ends_within_the_default_limits(capsys):
    code, out, err = vslsp(capsys, "plan", DOMAIN, FORALL, "--json")
    assert code == 1
    error = json.loads(out)["error"]
    assert f"memory limit of {DEFAULT_MEMORY_MB} MB reached" in error or "time limit" in error


@pytest.mark.parametrize("how", ["kill", "timeout"])
def test_sigterm_to_plan_leaves_no_planner_and_no_folder(tmp_path, how):
    args = ["plan", DOMAIN, FORALL, "--memory", "700"]
    if how == "timeout" and shutil.which("timeout") is None:
        pytest.skip("no timeout command")
    # coreutils' timeout, at its limit or sent SIGTERM, sends SIGTERM to the command and its group.
    process = start(args, tmp_path, prefix=("timeout", "600") if how == "timeout" else ())
    try:
        assert became_true(lambda: bool(planner_processes(process.pid)), process)
        planners = planner_processes(process.pid)
        process.send_signal(signal.SIGTERM)
        _, stderr = process.communicate(timeout=120)
    finally:
        process.kill()
    assert process.returncode in ((124, 143) if how == "timeout" else (143,)), stderr
    assert "Traceback" not in stderr
    wait_until(lambda: all(process_gone(pid) for pid in planners), f"the planners {planners} to end")
    assert list((tmp_path / "tmp").glob("vslsp-*")) == []


def test_a_fast_downward_failure_names_the_component_and_its_last_line():
    run = run_fast_downward("(define (domain broken", "(define (problem p))", DIRECT["fast-downward"], timeout=60)
    assert run.outcome is PlanStatus.INTERNAL_ERROR
    message = failure(run)
    assert message.startswith("Fast Downward's translator stopped with exit code")
    assert message.split(": ", 1)[1].strip()  # its last line, not an empty "failed:"
