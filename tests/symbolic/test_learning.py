"""Learning from grounded observations (paper: "Generalization of Learned Skills as Symbolic
Action Models", Table 3, and the iCub experiments' rules r_i^j)."""

import pytest
from helpers.symbolic import PDDL, demonstration, far, scene, step

from vslsp.errors import InputError
from vslsp.symbolic import (
    Forall,
    LearnedTask,
    Not,
    SometimeBefore,
    learn_domain,
    learn_task,
    make_problem,
    read_domain,
    solve,
    validate,
)


def test_table_3_is_learned_from_observed_executions(skill_executions):
    domain = learn_domain(skill_executions)
    push, pull = domain.action("push"), domain.action("pull")
    assert push.parameters == pull.parameters == (("?b", "block"),)
    assert push.precondition == Not(far("?b")) and push.effects == (far("?b"),)
    assert pull.precondition == far("?b") and pull.effects == (Not(far("?b")),)
    # The learned domain is the shipped one, action for action.
    assert domain == read_domain(PDDL / "domain.pddl")


def test_preconditions_are_intersected_over_executions():
    # Two predicates; "heavy" differs between the two pushes, so it is no precondition.
    executions = [
        step("push", "a", {"a": {"far": False, "heavy": True}}, a=True),
        step("push", "b", {"b": {"far": False, "heavy": False}}, b=True),
    ]
    push = learn_domain(executions).action("push")
    assert push.precondition == Not(far("?b"))
    assert {p.name for p in learn_domain(executions).predicates} == {"far", "heavy"}


def test_no_action_to_learn_is_an_input_error():
    with pytest.raises(InputError, match="no action to learn"):
        learn_domain([step("push", "red", scene(red=True))])


def test_keep_all_near_rules_eliminate_context_and_colour(keep_all_near_demonstrations):
    task = learn_task(keep_all_near_demonstrations)
    (rule,) = task.rules
    assert rule.obj == "?" and rule.effect == (("far", False),) and rule.context == ()
    assert set(rule.sources) == {(1, 1), (1, 2), (2, 1), (3, 1)}
    assert task.goal == Forall((("?b", "block"),), Not(far("?b")))
    assert task.constraints == ()


@pytest.mark.parametrize("colours", [("purple", "cyan"), ("red", "blue", "pink", "green", "orange", "white")])
def test_keep_all_near_generalises_to_unseen_colours_and_counts(keep_all_near_demonstrations, colours):
    domain = learn_domain(s for d in keep_all_near_demonstrations for s in d)
    task = learn_task(keep_all_near_demonstrations)
    state = scene(**{c: i % 2 == 0 for i, c in enumerate(colours)})
    problem = make_problem(domain, task, state)
    plan = solve(domain, problem)
    assert sorted(plan.steps) == sorted(("pull", (c,)) for c in colours[::2])
    assert validate(domain, problem, plan.steps).valid


def test_one_demonstration_teaches_the_order_as_sometime_before(pull_in_order_demonstration):
    task = learn_task([pull_in_order_demonstration])
    near = {c: Not(far(c)) for c in ("orange", "green", "yellow")}
    assert task.constraints == (
        SometimeBefore(near["green"], near["orange"]),
        SometimeBefore(near["yellow"], near["green"]),
    )
    assert [r.obj for r in task.rules] == ["orange", "green", "yellow"]
    assert task.without_order().constraints == () and task.without_order().goal == task.goal


def test_order_is_kept_only_where_demonstrations_agree():
    start = scene(a=True, b=True, c=True)
    task = learn_task(
        [
            demonstration(start, ("pull", "a"), ("pull", "b"), ("pull", "c")),
            demonstration(start, ("pull", "b"), ("pull", "a"), ("pull", "c")),
        ],
        ordered=True,
    )
    # a/b disagree; both come before c.
    pairs = {(str(c.formula.arg.args[0]), str(c.before.arg.args[0])) for c in task.constraints}
    assert pairs == {("c", "a"), ("c", "b")}


def test_ordered_false_lifts_a_single_demonstration(pull_in_order_demonstration):
    task = learn_task([pull_in_order_demonstration], ordered=False)
    assert task.constraints == () and isinstance(task.goal, Forall)


def test_opposite_effects_are_not_lifted():
    start = scene(red=False, green=True, blue=True)
    task = learn_task([demonstration(start, ("push", "red"), ("pull", "green"), ("pull", "blue"))], ordered=False)
    # "every block near" would contradict "red far": the rules stay per colour.
    assert {r.obj for r in task.rules} == {"red", "green", "blue"}
    assert not isinstance(task.goal, Forall)


def test_disagreeing_demonstrations_are_an_input_error():
    with pytest.raises(InputError, match="disagree about red"):
        learn_task(
            [demonstration(scene(red=False), ("push", "red")), demonstration(scene(red=True), ("pull", "red"))],
            ordered=True,
        )


def test_task_round_trips_through_json(pull_in_order_demonstration):
    task = learn_task([pull_in_order_demonstration])
    assert LearnedTask.from_dict(task.to_dict()) == task


def test_make_problem_states_the_task_in_the_scene(pull_in_order_demonstration, skill_executions):
    domain, task = learn_domain(skill_executions), learn_task([pull_in_order_demonstration])
    problem = make_problem(domain, task, scene(yellow=True, green=True, orange=True, red=False))
    assert problem.objects == tuple((c, "block") for c in ("yellow", "green", "orange", "red"))
    assert problem.init == {far(c) for c in ("yellow", "green", "orange")}
    assert problem.constraints == task.constraints
    with pytest.raises(InputError, match="names green, orange, yellow, not in the scene"):
        make_problem(domain, task, scene(red=True))


def test_replanning_halfway_keeps_only_the_order_still_ahead(pull_in_order_demonstration, skill_executions):
    domain, task = learn_domain(skill_executions), learn_task([pull_in_order_demonstration])
    # Orange and green are already near: only "yellow after green" is left, and it is kept.
    halfway = make_problem(domain, task, scene(orange=False, green=False, yellow=True))
    assert halfway.constraints == task.constraints[1:]
    assert solve(domain, halfway).lines() == ["pull yellow"]
    done = make_problem(domain, task, scene(orange=False, green=False, yellow=False))
    assert done.constraints == () and solve(domain, done).steps == ()
