"""Learning over user predicates (issue: symbol grounding as a user's workflow): action models,
rules and goals over every grounded predicate, with what no skill changes kept out."""

import pytest
from helpers.cli import vslsp_process

from vslsp.symbolic import Atom, Forall, Not, Step, learn_domain, learn_task, make_problem, solve


def _state(**objects: dict) -> dict:
    return {name: dict(values) for name, values in objects.items()}


def _values(far: bool, right: bool, colour: str) -> dict:
    return {"far": far, "on-robot-side": not far, "right-half": right, "warm": colour in ("red", "orange", "yellow")}


def _step(action: str, obj: str, right_before: bool, right_after: bool, others: dict | None = None) -> Step:
    far_before = action == "pull"
    before = {obj: _values(far_before, right_before, obj), **(others or {})}
    after = {obj: _values(not far_before, right_after, obj), **(others or {})}
    return Step(action, obj, before, after)


def test_a_user_predicate_the_skills_change_enters_the_models_and_a_static_one_stays_out():
    # Every explored cube was warm and the pushes all started in the right half: neither is needed.
    executions = [
        _step("push", "red", True, True),
        _step("push", "orange", True, True),
        _step("pull", "yellow", False, False),
        _step("pull", "red", True, True),
    ]
    domain = learn_domain(executions)
    push, pull = domain.action("push"), domain.action("pull")
    assert set(push.effects) == {Atom("far", ("?b",)), Not(Atom("on-robot-side", ("?b",)))}
    assert set(pull.effects) == {Not(Atom("far", ("?b",))), Atom("on-robot-side", ("?b",))}
    assert "warm" not in push.precondition.to_pddl() and "right-half" not in push.precondition.to_pddl()
    assert "(on-robot-side ?b)" in push.precondition.to_pddl()
    assert {p.name for p in domain.predicates} == {"far", "on-robot-side", "right-half", "warm"}


def test_an_effect_must_hold_in_every_execution():
    by_chance = [
        _step("push", "red", True, False),
        _step("push", "green", True, True),
        _step("pull", "blue", False, False),
    ]
    domain = learn_domain(by_chance)
    assert all(
        "right-half" not in a.precondition.to_pddl() + " ".join(e.to_pddl() for e in a.effects) for a in domain.actions
    )
    always = [
        _step("push", "red", True, False),
        _step("push", "green", True, False),
        _step("pull", "blue", False, False),
    ]
    push = learn_domain(always).action("push")
    assert Not(Atom("right-half", ("?b",))) in push.effects
    assert "(right-half ?b)" in push.precondition.to_pddl()  # a fluent the skill changes: needed before


def test_rules_keep_what_the_demonstrations_share_and_what_the_skill_changes():
    models = learn_domain([_step("push", "red", True, True), _step("pull", "blue", False, False)])
    # Three demonstrations pull cubes; one pull happened to carry a cube across the image's middle.
    demonstrations = [
        [_step("pull", "red", True, True)],
        [_step("pull", "green", True, False)],
        [_step("pull", "blue", False, False)],
    ]
    for task in (learn_task(demonstrations), learn_task(demonstrations, models=models)):
        (rule,) = task.rules
        assert rule.obj == "?" and rule.effect == (("far", False), ("on-robot-side", True))
        assert task.goal == Forall((("?b", "block"),), Not(Atom("far", ("?b",))) & Atom("on-robot-side", ("?b",)))
    # One demonstration: without the models the accident would be part of the goal.
    (demo,) = [[_step("pull", "green", True, False)]]
    assert "right-half" in learn_task([demo]).goal.to_pddl()
    task = learn_task([demo], models=models)
    assert "right-half" not in task.goal.to_pddl()
    problem = make_problem(models, task, _state(green=_values(True, True, "green")))
    assert solve(models, problem).lines() == ["pull green"]


@pytest.mark.slow
def test_keep_all_near_with_the_example_predicates_end_to_end(tmp_path):
    import json
    from pathlib import Path

    predicates = Path(__file__).parents[2] / "examples/grounding/predicates.py"
    result = vslsp_process(
        "experiment",
        "keep-all-near",
        "--predicates",
        predicates,
        "--trials",
        1,
        "--seed",
        5,
        "--out",
        tmp_path,
        "--json",
        timeout=900,
    )
    assert result.returncode == 0, result.stderr
    trial = json.loads(result.stdout)["results"][0]
    models = "\n".join(trial["action_models"])
    assert "pull: eff (not (far ?b)) (on-robot-side ?b)" in models and "warm" not in models
    assert trial["rules"][0].startswith("r_") and "<B_? -> not far, on-robot-side>" in trial["rules"][0]
    assert "(on-robot-side ?b)" in (tmp_path / "domain.pddl").read_text()
