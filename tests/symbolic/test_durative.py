"""The learned domain with durations (vslsp.symbolic.io.durative): push and pull written as durative
actions lasting their DMPs' 2τ, read clean by the language engine, planned by a temporal planner
and the plan validated in time."""

from __future__ import annotations

import json

import pytest
from helpers.cli import vslsp
from helpers.symbolic import PDDL

from vslsp.errors import InputError
from vslsp.skills.library import SkillLibrary, default_library_path
from vslsp.symbolic import read_domain
from vslsp.symbolic.io.durative import durative_domain_pddl, skill_durations
from vslsp.symbolic.language import check_files


def test_the_learned_skills_give_each_action_its_duration():
    durations = skill_durations(SkillLibrary.load(default_library_path()))
    assert set(durations) >= {"push", "pull"}
    assert all(0.1 < d < 60 for d in durations.values())


def test_the_durative_domain_checks_plans_and_validates(capsys, tmp_path):
    durations = {"push": 3.25, "pull": 2.5}
    text = durative_domain_pddl(read_domain(PDDL / "domain.pddl"), durations)
    assert "(:durative-action pull" in text and ":duration (= ?duration 2.500)" in text
    assert ":condition (at start (far ?b))" in text and "(at end (not (far ?b)))" in text
    domain = tmp_path / "domain.pddl"
    domain.write_text(text)
    assert [d.format() for d in check_files(str(domain), None).diagnostics] == []
    problem, plan = PDDL / "simple-push-pull.pddl", tmp_path / "plan"
    code, out, _ = vslsp(capsys, "plan", domain, problem, "--json", "--out", plan)
    result = json.loads(out)
    assert code == 0 and result["kind"] == "temporal" and result["makespan"] >= 2.5
    assert {s["duration"] for s in result["steps"]}.issubset({3.25, 2.5})  # the planned durations are the domain's
    code, out, _ = vslsp(capsys, "validate", domain, problem, plan, "--json")
    assert code == 0 and json.loads(out)["valid"] is True


def test_an_action_without_a_duration_is_named():
    with pytest.raises(InputError, match="action push has no positive duration"):
        durative_domain_pddl(read_domain(PDDL / "domain.pddl"), {"pull": 2.0})


def test_the_demonstrated_order_with_durations_is_refused_on_its_line(capsys, tmp_path):
    domain = tmp_path / "domain.pddl"
    domain.write_text(durative_domain_pddl(read_domain(PDDL / "domain.pddl"), {"push": 3.0, "pull": 3.0}))
    problem = PDDL / "pull-in-order.pddl"
    line = next(n for n, text in enumerate(problem.read_text().splitlines(), 1) if "(:constraints" in text)
    code, _, err = vslsp(capsys, "plan", domain, problem)
    assert (
        code == 2 and f"{problem}:{line}:" in err and "PDDL 3.0 constraints (:constraints ...) are not planned" in err
    )
