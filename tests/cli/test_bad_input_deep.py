"""Deep and huge PDDL input and the PDDL commands' options (issue 42): each case an attacker measured,
and its neighbours, ends in exit 2 with one line saying what was wrong and the limit, before the work
it would have taken; no traceback. The limits are vslsp.symbolic.budget's; time and peak memory per
case are measured by benchmarks/bench_deep_inputs.py (a test does not read the clock)."""

from __future__ import annotations

import io

import pytest
from helpers.cli import REPO, vslsp

from vslsp.errors import InputError
from vslsp.shell.session import Shell
from vslsp.symbolic import budget, read_pddl
from vslsp.symbolic.budget import MAX_GROUND_INSTANCES, MAX_NESTING, MAX_READER_TYPE_DEPTH, MAX_TYPE_DEPTH
from vslsp.symbolic.language import RESERVED_NAMES, is_reserved_name

DOMAIN = REPO / "pddl" / "domain.pddl"
PROBLEM = REPO / "pddl" / "pull-in-order.pddl"


def problem_with(goal: str, objects: str = "a - block", constraints: str = "", domain: str = "vsl-sp") -> str:
    section = f" (:constraints {constraints})" if constraints else ""
    return f"(define (problem p) (:domain {domain}) (:objects {objects}) (:init) (:goal {goal}){section})\n"


def nested(head: str, inner: str, levels: int) -> str:
    return f"({head} " * levels + inner + ")" * levels


def type_chain(depth: int) -> str:
    """A domain whose type t0 is ``depth`` types below object (t0 - t1 - ... - t{depth-1})."""
    types = " ".join(f"t{i} - t{i + 1}" for i in range(depth - 1)) + f" t{depth - 1}"
    return (
        "(define (domain chain) (:requirements :strips :typing :negative-preconditions)\n"
        f" (:types {types})\n (:predicates (p ?x - t0))\n"
        " (:action a :parameters (?x - t0) :precondition (p ?x) :effect (not (p ?x))))\n"
    )


CHAIN_PROBLEM = "(define (problem q) (:domain chain) (:objects x - t0) (:init (p x)) (:goal (not (p x))))\n"


def one_line(err: str) -> str:
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


def shell_output(script: str) -> str:
    out = io.StringIO()
    shell = Shell(stdin=io.StringIO(script), stdout=out)
    shell.use_rawinput = False
    shell.cmdloop()
    return out.getvalue()


# --- nesting -----------------------------------------------------------------------------------------


def test_an_and_nested_a_hundred_thousand_deep_is_refused_by_pddl_check(capsys, tmp_path):
    path = tmp_path / "deep.pddl"
    path.write_text(problem_with(nested("and", "(far a)", 100_000)))
    code, out, err = vslsp(capsys, "pddl", "check", DOMAIN, path)
    assert code == 2 and "Traceback" not in out + err, err
    assert out.strip().splitlines() == [
        f"{path}:1:5064: error: parentheses nest 1001 deep here: nested too deeply (limit 1000); "
        "flatten the formula: (and a (and b c)) is (and a b c)"
    ]


@pytest.mark.parametrize("command", ["plan", "validate", "shell"])
def test_the_same_file_is_refused_on_the_planners_path_before_its_reader(capsys, tmp_path, command):
    path = tmp_path / "deep.pddl"
    path.write_text(problem_with(nested("and", "(far a)", 100_000)))
    plan = tmp_path / "plan.txt"
    plan.write_text("(push a)\n")
    args = ("pddl", "shell") if command == "shell" else (command,)
    code, _, err = vslsp(capsys, *args, DOMAIN, path, *([plan] if command == "validate" else []))
    assert code == 2 and "parentheses nest 41 deep here" in one_line(err)


def test_the_shell_load_command_says_the_file_nests_too_deeply(tmp_path):
    path = tmp_path / "deep.pddl"
    path.write_text(problem_with(nested("and", "(far a)", 100_000)))
    out = shell_output(f"load {DOMAIN} {path}\nshow problem\n")
    assert "error: " in out and "parentheses nest 41 deep here" in out and "loaded" not in out


@pytest.mark.parametrize(
    "command",
    [
        "goal {}",
        "constraint {}",
        "init {}",
        "drop init {}",
        "validate (push {})",
        "predicate {}",
        "action a :effect {} ",
    ],
)
def test_every_shell_command_refuses_what_is_typed_too_deeply_nested(command):
    typed = command.format(nested("far", "a", 100_000))
    out = shell_output(f"load {DOMAIN}\nobjects a - block\n{typed}\n")
    assert "error: parentheses nest 41 deep at column" in out and "nested too deeply (limit 40)" in out, out[-300:]


SHAPES = {
    "and": lambda n: problem_with(nested("and", "(far a)", n)),
    "not": lambda n: problem_with(nested("not", "(far a)", n)),
    "or": lambda n: problem_with(nested("or", "(far a)", n)),
    "imply": lambda n: problem_with(nested("imply (far a)", "(far a)", n)),
    "forall": lambda n: problem_with(nested("forall (?x - block)", "(far ?x)", n)),
    "unknown-predicate": lambda n: problem_with(nested("foo", "(far a)", n)),
    "constraint": lambda n: problem_with("(far a)", constraints=nested("and", "(always (far a))", n - 1)),
}


@pytest.mark.parametrize("shape", SHAPES)
@pytest.mark.parametrize("depth", [MAX_NESTING, MAX_NESTING + 1])
def test_every_shape_of_formula_is_checked_up_to_the_limit_and_refused_past_it(capsys, tmp_path, shape, depth):
    path = tmp_path / "shape.pddl"
    path.write_text(SHAPES[shape](depth - 3))  # (define, (:goal and the atom are three levels
    code, out, err = vslsp(capsys, "pddl", "check", DOMAIN, path)
    assert "Traceback" not in out + err and "internal error" not in err, err
    too_deep = "nested too deeply (limit 1000)" in out
    assert too_deep == (depth > MAX_NESTING), out[-300:]
    assert code == 2 if too_deep else code in (0, 2)


def test_an_effect_nested_to_the_limit_is_checked(capsys, tmp_path):
    path = tmp_path / "domain.pddl"
    effect = nested("and", "(far ?b)", MAX_NESTING - 3)
    path.write_text(DOMAIN.read_text().replace(":effect (far ?b))", f":effect {effect})", 1))
    code, out, err = vslsp(capsys, "pddl", "check", path)
    assert code == 0 and out.strip().endswith("ok"), out[-300:] + err


# --- types -------------------------------------------------------------------------------------------


def test_a_type_chain_twenty_thousand_deep_is_refused_at_once(capsys, tmp_path):
    path = tmp_path / "chain.pddl"
    path.write_text(type_chain(20_000))
    code, out, err = vslsp(capsys, "pddl", "check", path)
    assert code == 2 and "the type hierarchy is 20000 types deep: nested too deeply (limit 1000)" in out, out
    problem = tmp_path / "p.pddl"
    problem.write_text(CHAIN_PROBLEM)
    code, _, err = vslsp(capsys, "plan", path, problem)
    assert code == 2 and "20000 types deep: nested too deeply (limit 500 on the planner's path)" in one_line(err)


def test_type_chains_at_the_limits_are_read(capsys, tmp_path):
    path = tmp_path / "chain.pddl"
    path.write_text(type_chain(MAX_TYPE_DEPTH))
    code, out, _ = vslsp(capsys, "pddl", "check", path)
    assert code == 0 and "1000 types" in out
    path.write_text(type_chain(MAX_TYPE_DEPTH + 1))
    code, out, _ = vslsp(capsys, "pddl", "check", path)
    assert code == 2 and "1001 types deep" in out
    problem = tmp_path / "p.pddl"
    problem.write_text(CHAIN_PROBLEM)
    path.write_text(type_chain(MAX_READER_TYPE_DEPTH))
    domain, read = read_pddl(path, problem)
    assert read is not None and len(domain.types) == MAX_READER_TYPE_DEPTH and "t0" in domain.subtypes("t499")
    path.write_text(type_chain(MAX_READER_TYPE_DEPTH + 1))
    with pytest.raises(InputError, match="501 types deep"):
        read_pddl(path, problem)


def test_a_type_cycle_in_a_long_chain_is_found_and_placed(capsys, tmp_path):
    path = tmp_path / "cycle.pddl"
    path.write_text(type_chain(5000).replace(" t4999)", " t4999 - t2)"))
    code, out, _ = vslsp(capsys, "pddl", "check", path)
    assert code == 2 and "the types form a cycle (t2 - t3 - " in out and "t4999 - t2)" in out


def test_the_shell_refuses_a_type_deeper_than_the_planners_path_takes():
    script = "type t0\n" + "".join(f"type t{i} - t{i - 1}\n" for i in range(1, MAX_READER_TYPE_DEPTH + 1))
    out = shell_output(script)
    assert "type t499 - t498" in out
    assert f"error: type t{MAX_READER_TYPE_DEPTH} under t{MAX_READER_TYPE_DEPTH - 1} would be 501 types deep" in out


# --- huge lists --------------------------------------------------------------------------------------


def test_the_shell_takes_a_hundred_thousand_objects_on_one_line():
    names = " ".join(f"o{i}" for i in range(100_000))
    out = shell_output(f"type block\nobjects {names} - block\nobjects o5 - block\n")
    assert "- block; 100000 in all" in out and out.count("error") == 0


def test_the_shell_takes_long_initial_states_and_goals_among_many_objects():
    names = " ".join(f"o{i}" for i in range(50_000))
    init = " ".join(f"(far o{i})" for i in range(0, 50_000, 2))
    goal = " ".join(f"(far o{i})" for i in range(0, 20_000, 2))
    out = shell_output(f"load {DOMAIN}\nobjects {names} - block\ninit {init}\ngoal (and {goal})\nvalidate (push o1)\n")
    assert "true initially: (far o0) (far o2)" in out and "goal (and (far o0) (far o2)" in out, out[-500:]
    assert "valid: the plan reaches the goal in 1 step" in out and "error" not in out


def test_the_shell_takes_twenty_thousand_types_on_one_line():
    names = " ".join(f"t{i}" for i in range(20_000))
    out = shell_output(f"type block\ntype {names} - block\ntype x - t7\nobjects y - nothing\n")
    assert "type x - t7" in out and "t18 and 19982 more)" in out  # a short message, whatever the number of types


def test_a_triply_quantified_at_most_once_over_300_objects_is_counted_not_built(capsys, tmp_path):
    domain = tmp_path / "tri.pddl"
    domain.write_text(
        "(define (domain tri) (:requirements :strips :typing :constraints) (:types obj)\n"
        " (:predicates (r ?a ?b ?c - obj) (s))\n (:action act :parameters (?a ?b ?c - obj) :precondition (s)"
        " :effect (r ?a ?b ?c)))\n"
    )
    problem = tmp_path / "p.pddl"
    objects = " ".join(f"o{i}" for i in range(300)) + " - obj"
    problem.write_text(
        f"(define (problem p) (:domain tri) (:objects {objects}) (:init (s)) (:goal (r o0 o1 o2))\n"
        " (:constraints (forall (?a ?b ?c - obj) (at-most-once (r ?a ?b ?c)))))\n"
    )
    plan = tmp_path / "plan.txt"
    plan.write_text("(act o0 o1 o2)\n")
    for command in (["validate", domain, problem, plan], ["plan", domain, problem]):
        code, _, err = vslsp(capsys, *command)
        line = one_line(err)
        assert code == 2 and line.startswith(f"error: {problem}: the constraint (forall (?a - obj ?b - obj ?c - obj)")
        assert "27,000,000 ground instances; vslsp writes out at most 200,000" in line


def test_ground_instances_are_counted_against_the_limit_exactly():
    universe = {"obj": tuple(f"o{i}" for i in range(MAX_GROUND_INSTANCES))}
    assert budget.instance_count((("?a", "obj"),), universe) == MAX_GROUND_INSTANCES
    budget.check_instances(MAX_GROUND_INSTANCES, "the goal")
    with pytest.raises(InputError, match="the goal has 200,001 ground instances"):
        budget.check_instances(MAX_GROUND_INSTANCES + 1, "the goal")


def test_a_quantified_goal_past_the_limit_is_refused_before_it_is_written_out():
    from vslsp.symbolic.model.formula import Atom, Forall, expand_quantifiers

    universe = {"block": tuple(f"b{i}" for i in range(100))}
    goal = Forall((("?a", "block"), ("?b", "block"), ("?c", "block")), Atom("on", ("?a", "?b")))
    with pytest.raises(InputError, match="the goal has 1,000,000 ground instances"):
        expand_quantifiers(goal, universe, "the goal")
    assert len(expand_quantifiers(Forall((("?a", "block"),), Atom("far", ("?a",))), universe).args) == 100


def test_a_flat_goal_of_twenty_thousand_atoms_is_read_and_its_plan_validated(capsys, tmp_path):
    path = tmp_path / "flat.pddl"
    objects = " ".join(f"o{i}" for i in range(20_000)) + " - block"
    path.write_text(problem_with("(and " + " ".join(f"(far o{i})" for i in range(20_000)) + ")", objects))
    plan = tmp_path / "plan.txt"
    plan.write_text("".join(f"(push o{i})\n" for i in range(20_000)))
    code, out, err = vslsp(capsys, "validate", DOMAIN, path, plan)
    assert code == 0 and out == "valid: the plan reaches the goal in 20000 steps\n", err
    plan.write_text("".join(f"(push o{i})\n" for i in range(19_999)))
    code, out, _ = vslsp(capsys, "validate", DOMAIN, path, plan)
    assert code == 1 and out.startswith("invalid: the goal (far o19999) does not hold after the last step")
    plan.write_text("(push o0)\n")  # 19,999 goal conjuncts false, each found where it is written
    code, out, _ = vslsp(capsys, "validate", DOMAIN, path, plan)
    lines = out.splitlines()
    assert code == 1 and len(lines) == 20_000 and lines[-1].startswith(f"  {path}:1:")
    assert lines[-1].endswith(": the goal (far o19999) does not hold after the last step")


def test_twenty_thousand_unknown_names_among_twenty_thousand_objects_are_each_reported(capsys, tmp_path):
    # did-you-mean compares at most MAX_SUGGESTION_COMPARISONS names in all: the first errors get one
    path = tmp_path / "unknown.pddl"
    objects = " ".join(f"o{i}" for i in range(20_000)) + " - block"
    path.write_text(problem_with("(and " + " ".join(f"(far x{i})" for i in range(20_000)) + ")", objects))
    code, out, err = vslsp(capsys, "pddl", "check", DOMAIN, path)
    lines = out.splitlines()
    assert code == 2 and len(lines) == 20_000 and err == "20000 errors, 0 warnings\n"
    assert lines[10].endswith("error: unknown object or constant 'x10' (did you mean 'o10'?)"), lines[10]
    assert lines[-1].endswith("error: unknown object or constant 'x19999'"), lines[-1]
    assert sum("did you mean" in line for line in lines) == budget.MAX_SUGGESTION_COMPARISONS // 20_000


# --- the phases' budgets -----------------------------------------------------------------------------


def test_each_phase_says_which_ran_out_of_time(monkeypatch, capsys, tmp_path):
    path = tmp_path / "big.pddl"
    objects = " ".join(f"o{i}" for i in range(20_000))
    path.write_text(problem_with("(and " + " ".join(f"(far o{i})" for i in range(20_000)) + ")", f"{objects} - block"))
    monkeypatch.setattr(budget, "PHASE_BUDGET_S", 0.001)
    code, _, err = vslsp(capsys, "pddl", "check", DOMAIN, path)
    assert code == 2 and one_line(err) == (
        f"error: {path}: checking took more than 0.001 s and was stopped; the file is too large for vslsp's "
        "checker; split it"
    )
    monkeypatch.setattr(budget, "PHASE_BUDGET_S", 60.0)
    domain, problem = read_pddl(DOMAIN, PROBLEM)
    from vslsp.symbolic import validate

    assert problem is not None
    monkeypatch.setattr(budget, "PHASE_BUDGET_S", 0.001)
    with pytest.raises(InputError, match="the plan for problem pull-in-order: validating took more than 0.001 s"):
        validate(domain, problem, [("pull", ("orange",))] * 200_000)


def test_a_phase_inside_another_is_governed_by_the_outer_one():
    with budget.phase("validating", "outer", 30), budget.phase("reading", "inner", 0.001):
        sum(range(100_000))  # the inner budget set no timer of its own


# --- names and the problem's domain -----------------------------------------------------------------


@pytest.mark.parametrize("name", ["and", "or", "not", "forall", "AND", "at-most-once", "either"])
def test_an_object_named_as_a_word_of_pddl_is_refused_everywhere(capsys, tmp_path, name):
    path = tmp_path / "p.pddl"
    path.write_text(problem_with("(far a)", f"a {name} - block"))
    code, out, _ = vslsp(capsys, "pddl", "check", DOMAIN, path)
    message = f"'{name}' is a word of PDDL ({name.lower()} ...), so it cannot name an object"
    assert code == 2 and f"{path}:1:50: error: {message}" in out, out
    code, _, err = vslsp(capsys, "plan", DOMAIN, path)
    # plan refuses it as pddl check does: at the same place, the name as written
    assert code == 2 and one_line(err) == f"error: {path}:1:50: {message}; choose another name (e.g. '{name}-1')"
    assert "error: " + message in shell_output(f"load {DOMAIN}\ntype block\nobjects {name} - block\n")


def test_predicates_types_and_actions_named_as_words_of_pddl_are_refused(capsys, tmp_path):
    path = tmp_path / "d.pddl"
    path.write_text(
        "(define (domain d) (:requirements :strips :typing) (:types when)\n"
        " (:predicates (or) (q ?x - when)) (:action forall :parameters () :precondition (and) :effect (or)))\n"
    )
    code, out, _ = vslsp(capsys, "pddl", "check", path)
    assert code == 2
    for what, name in (("type", "when"), ("predicate", "or"), ("action", "forall")):
        assert (
            f"'{name}' is a word of PDDL ({name} ...), so it cannot name a{'n' if what == 'action' else ''} {what}"
            in out
        )


def test_at_is_a_predicate_name_and_no_reserved_word(capsys, tmp_path):
    assert not is_reserved_name("at") and "at" not in RESERVED_NAMES and {"and", "or", "not"} <= RESERVED_NAMES
    domain = tmp_path / "d.pddl"
    domain.write_text(
        "(define (domain d) (:requirements :strips :typing) (:types loc)\n"
        " (:predicates (at ?l - loc)) (:action go :parameters (?l - loc) :precondition (and) :effect (at ?l)))\n"
    )
    problem = tmp_path / "p.pddl"
    problem.write_text("(define (problem p) (:domain d) (:objects home - loc) (:init) (:goal (at home)))\n")
    code, out, err = vslsp(capsys, "pddl", "check", domain, problem)
    assert code == 0 and out.strip().endswith("ok"), out + err
    assert read_pddl(domain, problem)[1] is not None


@pytest.mark.parametrize("command", ["plan", "validate", "shell"])
def test_a_problem_for_another_domain_is_refused(capsys, tmp_path, command):
    path = tmp_path / "p.pddl"
    path.write_text(problem_with("(far a)", domain="blocks"))
    plan = tmp_path / "plan.txt"
    plan.write_text("(push a)\n")
    args = ("pddl", "shell") if command == "shell" else (command,)
    code, _, err = vslsp(capsys, *args, DOMAIN, path, *([plan] if command == "validate" else []))
    assert code == 2 and one_line(err) == (
        f"error: {path}:1:30: the problem is for domain 'blocks', but the domain file defines 'vsl-sp'; "
        "give the domain file of 'blocks', or write (:domain vsl-sp) in the problem"
    )
    code, out, _ = vslsp(capsys, "pddl", "check", DOMAIN, path)
    assert code == 2 and f"{path}:1:30: error: the problem is for domain 'blocks'" in out


# --- options -----------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "value, message",
    [
        ("nan", "nan is not a finite number"),
        ("inf", "inf is not a finite number"),
        ("1e300", "1e300 is larger than 604800.0"),
        ("-1", "-1 is negative; give a number >= 0"),
        ("x", "'x' is not a number"),
    ],
)
def test_the_conflict_budget_is_a_finite_number_in_range(capsys, value, message):
    code, out, err = vslsp(capsys, "plan", DOMAIN, "missing.pddl", "--conflict-budget", value)
    assert code == 2 and out == "" and f"Invalid value for '--conflict-budget': {message}" in err, err
    assert "missing.pddl" not in err  # checked before the files are read
