"""Numeric and temporal PDDL (vslsp.symbolic.engines.pddl21): ``vslsp pddl check``, ``plan`` and ``validate``
on real domains of tests/data/pddl21, planned by the real engines (ENHSP in Java, TAMER, Aries);
what no engine plans is exit 2 with one line naming the construct and its place."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from helpers.cli import vslsp

DATA = Path(__file__).resolve().parents[1] / "data" / "pddl21"
CASES = [
    ("rover-numeric-domain.pddl", "rover-numeric-problem.pddl", "numeric", "enhsp"),
    ("counters-domain.pddl", "counters-problem.pddl", "numeric", "enhsp"),
    ("rover-temporal-domain.pddl", "rover-temporal-problem.pddl", "temporal", "aries"),
    ("rover-temporal-domain.pddl", "rover-timed-problem.pddl", "temporal", "aries"),
]


@pytest.mark.parametrize(("domain", "problem", "kind", "planner"), CASES)
def test_checks_plans_and_validates(capsys, tmp_path, domain, problem, kind, planner):
    code, out, _ = vslsp(capsys, "pddl", "check", DATA / domain, DATA / problem, "--json")
    assert code == 0 and json.loads(out)["diagnostics"] == []
    plan = tmp_path / "plan"
    code, out, _ = vslsp(capsys, "plan", DATA / domain, DATA / problem, "--json", "--out", plan)
    result = json.loads(out)
    assert code == 0 and result["planner"] == planner and result["kind"] == kind and result["plan"]
    assert (result["makespan"] is not None) == (kind == "temporal")
    code, out, _ = vslsp(capsys, "validate", DATA / domain, DATA / problem, plan, "--json")
    assert code == 0 and json.loads(out)["valid"] is True


def test_the_battery_is_recharged_and_the_metric_reported(capsys, tmp_path):
    plan = tmp_path / "plan"
    domain, problem = DATA / "rover-numeric-domain.pddl", DATA / "rover-numeric-problem.pddl"
    code, out, err = vslsp(capsys, "plan", domain, problem, "--out", plan)
    assert code == 0 and "(recharge curiosity base)" in out and "enhsp (numeric)" in err
    code, out, _ = vslsp(capsys, "validate", domain, problem, plan)
    assert code == 0 and out.startswith("valid: the plan reaches the goal (metric ")


def test_planner_named_and_planner_not_installed(capsys):
    domain, problem = DATA / "counters-domain.pddl", DATA / "counters-problem.pddl"
    code, out, _ = vslsp(capsys, "plan", domain, problem, "--planner", "tamer", "--json")
    assert code == 0 and json.loads(out)["planner"] == "tamer"
    code, _, err = vslsp(capsys, "plan", domain, problem, "--planner", "fast-downward")
    assert code == 2 and "planner fast-downward plans STRIPS and ADL without numbers or time" in err
    code, _, err = vslsp(capsys, "plan", domain, problem, "--planner", "aries")  # fails on numeric fluents
    assert code == 2 and "planner aries cannot plan this numeric problem" in err and "--planner enhsp" in err
    code, _, err = vslsp(capsys, "plan", domain, problem, "--planner", "nope")
    assert code == 2 and "planner nope is not installed (numeric and temporal problems: enhsp, tamer, aries" in err


def test_a_drive_on_an_empty_battery_is_placed_in_the_plan(capsys, tmp_path):
    plan = tmp_path / "plan"
    plan.write_text(
        "(drive curiosity base hill)\n(sample curiosity hill)\n; no recharge\n(drive curiosity hill crater)\n"
    )
    domain, problem = DATA / "rover-numeric-domain.pddl", DATA / "rover-numeric-problem.pddl"
    code, out, _ = vslsp(capsys, "validate", domain, problem, plan, "--json")
    verdict = json.loads(out)
    assert code == 1 and verdict["valid"] is False
    (violation,) = verdict["violations"]
    assert (violation["step"], violation["line"], violation["column"]) == (3, 4, 1)
    assert "battery(curiosity)" in violation["message"]
    code, out, _ = vslsp(capsys, "validate", domain, problem, plan)
    assert code == 1 and f"{plan}:4:1: step 3: Preconditions" in out


def test_each_false_goal_is_placed_in_the_problem(capsys, tmp_path):
    plan = tmp_path / "plan"
    plan.write_text("(drive curiosity base hill)\n")
    problem = DATA / "rover-numeric-problem.pddl"
    code, out, _ = vslsp(capsys, "validate", DATA / "rover-numeric-domain.pddl", problem, plan, "--json")
    verdict = json.loads(out)
    assert code == 1 and [(v["kind"], v["line"], v["column"]) for v in verdict["violations"]] == [
        ("goal", 10, 15),
        ("goal", 10, 30),
    ]


def test_temporal_plans_are_checked_in_time(capsys, tmp_path):
    domain, problem = DATA / "rover-temporal-domain.pddl", DATA / "rover-temporal-problem.pddl"
    plan = tmp_path / "plan"
    plan.write_text("0.0: (drive curiosity base crater) [4.0]\n0.0: (sample curiosity hill) [2.0]\n")
    code, out, _ = vslsp(capsys, "validate", domain, problem, plan)
    assert code == 1 and f"{plan}:1:1: step 1 at time 0: Conflicting effects at time 0" in out
    plan.write_text("0.0: (drive curiosity base crater) [3.0]\n")  # the domain says 4
    code, out, _ = vslsp(capsys, "validate", domain, problem, plan)
    assert code == 1 and "?duration constraint do not hold (at time 0)" in out
    plan.write_text("(drive curiosity base crater)\n")
    code, _, err = vslsp(capsys, "validate", domain, problem, plan)
    assert code == 2 and f"{plan}:1:1: a temporal plan's step starts with its time" in err


def test_the_printed_plan_is_a_plan_file(capsys, tmp_path):
    domain, problem = DATA / "rover-temporal-domain.pddl", DATA / "rover-temporal-problem.pddl"
    code, out, _ = vslsp(capsys, "plan", domain, problem)
    plan = tmp_path / "plan"
    plan.write_text(out)  # "1. 0.000: (drive ...) [4.000]" lines
    assert code == 0 and out.startswith("1. 0.000: (")
    code, out, _ = vslsp(capsys, "validate", domain, problem, plan)
    assert code == 0 and out.startswith("valid")


def test_a_road_that_opens_later_is_waited_for(capsys):
    code, out, _ = vslsp(
        capsys, "plan", DATA / "rover-temporal-domain.pddl", DATA / "rover-timed-problem.pddl", "--json"
    )
    (drive, _sample) = json.loads(out)["steps"]
    assert code == 0 and drive["action"] == "drive" and drive["start"] >= 3


def test_a_plan_naming_what_is_not_there_is_exit_2(capsys, tmp_path):
    plan = tmp_path / "plan"
    domain, problem = DATA / "counters-domain.pddl", DATA / "counters-problem.pddl"
    for text, message in (
        ("(increment c9)\n", ":1:1: no object 'c9' in the problem"),
        ("\n(incremnt c0)\n", ":2:1: no action 'incremnt' in the domain"),
        ("(increment)\n", ":1:1: increment takes 1 arguments, given 0"),
    ):
        plan.write_text(text)
        code, _, err = vslsp(capsys, "validate", domain, problem, plan)
        assert code == 2 and f"{plan}{message}" in err


def test_unsolvable_is_exit_1(capsys, tmp_path):
    problem = tmp_path / "p.pddl"
    problem.write_text(
        (DATA / "counters-problem.pddl").read_text().replace("(:goal (and", "(:goal (and (>= (value c0) 7)")
    )
    code, out, _ = vslsp(capsys, "plan", DATA / "counters-domain.pddl", problem, "--json")
    assert code == 1 and json.loads(out)["plan"] is None


@pytest.mark.parametrize(
    ("text", "planned", "checked"),
    [
        (None, "derived-domain.pddl:6:4: derived predicates (:derived ...) are not supported", "6:4: error: derived"),
        (
            "(:process fill :parameters () :precondition () :effect ())",
            "domain.pddl:10:4: PDDL+ processes (:process ...) are not supported",
            "10:4: error: PDDL+ processes (:process ...) are not supported",
        ),
    ],
)
def test_what_no_engine_plans_is_one_line_exit_2(capsys, tmp_path, text, planned, checked):
    domain = DATA / "derived-domain.pddl"
    problem = DATA / "derived-problem.pddl"
    if text is not None:
        domain = tmp_path / "domain.pddl"
        counters = (DATA / "counters-domain.pddl").read_text()
        domain.write_text(counters.replace("(:action decrement", text + "\n  (:action decrement"))
        problem = DATA / "counters-problem.pddl"
    code, _, err = vslsp(capsys, "plan", domain, problem)
    assert code == 2 and planned in err and "Traceback" not in err and len(err.strip().splitlines()) == 1
    code, out, _ = vslsp(capsys, "pddl", "check", domain, problem)
    assert code == 2 and checked in out.splitlines()[0]


def test_a_syntax_error_is_placed_in_its_file(capsys, tmp_path):
    problem = tmp_path / "p.pddl"
    problem.write_text((DATA / "counters-problem.pddl").read_text().replace("(= (max-int) 6)", "(= (max-int) six)"))
    code, _, err = vslsp(capsys, "plan", DATA / "counters-domain.pddl", problem)
    assert code == 2 and str(problem) in err and "Traceback" not in err


def test_enhsp_without_java_says_so(capsys, tmp_path, monkeypatch):
    monkeypatch.setenv("PATH", str(tmp_path))  # a PATH with no java on it
    code, _, err = vslsp(capsys, "plan", DATA / "counters-domain.pddl", DATA / "counters-problem.pddl")
    assert code == 2 and "planner enhsp (ENHSP) needs Java 17 or later and no 'java' is on PATH" in err


def test_the_time_limit_holds_for_an_engine_without_one(capsys, tmp_path):
    counters = " ".join(f"c{i}" for i in range(12))
    values = " ".join(f"(= (value c{i}) 0)" for i in range(12))
    problem = tmp_path / "p.pddl"  # unsolvable (max-int is one short) in a state space far too large to exhaust
    problem.write_text(
        f"(define (problem counters-hard) (:domain counters) (:objects {counters} - counter)\n"
        f"  (:init (= (max-int) 100000) {values})\n  (:goal (>= (value c0) 100001)))\n"
    )
    code, out, _ = vslsp(
        capsys, "plan", DATA / "counters-domain.pddl", problem, "--planner", "tamer", "--timeout", "1", "--json"
    )
    result = json.loads(out)
    assert code == 1 and result["status"] == "timeout" and "time limit of 1 s reached" in result["error"]
