"""``vslsp pddl shell``: a domain and a problem authored step by step from typed commands,
checked by the PDDL reader as they come, then planned, validated, saved and loaded."""

import io

from helpers.cli import vslsp_process
from helpers.symbolic import PDDL

from vslsp.symbolic import read_pddl
from vslsp.symbolic.shell import Shell

SESSION = """\
domain vsl-sp
type block
predicate (far ?b - block)
action push :parameters (?b - block) :precondition (not (far ?b)) :effect (far ?b)
action pull :parameters (?b - block) :precondition (far ?b) :effect (not (far ?b))
action lift :parameters (?b - block) :precondition (high ?b) :effect (far ?b)
problem pull-in-order
objects orange green yellow - block
init (far orange) (far green) (far yellow)
goal (and (not (far orange)) (not (far green)) (not (far yellow)))
constraint (sometime-before (not (far green)) (not (far orange)))
constraint (somewhere-after (not (far yellow)) (not (far green)))
constraint (sometime-before (not (far yellow)) (not (far green)))
plan
validate (pull green) (pull orange) (pull yellow)
save {folder}/domain.pddl {folder}/problem.pddl
drop constraints
validate (pull green) (pull orange) (pull yellow)
fly away
"""


def run(script: str, **kwargs) -> str:
    out = io.StringIO()
    shell = Shell(stdin=io.StringIO(script), stdout=out, **kwargs)
    shell.use_rawinput = False
    shell.cmdloop()
    return out.getvalue()


def test_a_scripted_session_builds_plans_and_validates(tmp_path):
    out = run(SESSION.format(folder=tmp_path))
    assert "error: unknown predicate or operator 'high'" in out
    assert "error: PDDL 3.0 has no 'somewhere-after'" in out
    assert "1. pull orange\n2. pull green\n3. pull yellow\n" in out
    assert "invalid: constraint (sometime-before (not (far green)) (not (far orange))) is broken" in out
    assert "valid: the plan reaches the goal in 3 steps\n" in out  # once the order is dropped
    assert "error: unknown command 'fly'" in out
    # each command says what it changed
    for said in (
        "type block",
        "predicate (far ?b - block)",
        "action push added; actions: push",
        "true initially: (far orange) (far green) (far yellow)",
        "constraint (sometime-before (not (far green)) (not (far orange))); 1 constraint",
        "dropped 2 constraints",
    ):
        assert f"(vslsp) {said}\n" in out, said
    # What was saved is the shipped pull-in-order experiment.
    saved_domain, saved_problem = read_pddl(tmp_path / "domain.pddl", tmp_path / "problem.pddl")
    shipped_domain, shipped_problem = read_pddl(PDDL / "domain.pddl", PDDL / "pull-in-order.pddl")
    assert saved_domain == shipped_domain
    assert (saved_problem.init, saved_problem.goal, saved_problem.constraints) == (
        shipped_problem.init,
        shipped_problem.goal,
        shipped_problem.constraints,
    )


def test_load_and_complete_names():
    out = run(f"load {PDDL / 'domain.pddl'} {PDDL / 'keep-all-near.pddl'}\nplan\n")
    assert "loaded domain vsl-sp and problem keep-all-near" in out and "3 steps" in out
    shell = Shell(*read_pddl(PDDL / "domain.pddl", PDDL / "keep-all-near.pddl"))
    assert shell.completedefault("(f", "init (f", 5, 7) == ["far", "forall"]
    assert "pull" in shell.completedefault("pu", "validate (pu", 10, 12)


def test_vslsp_shell_is_the_pddl_shell_at_the_top_level(tmp_path):
    done = vslsp_process("shell", PDDL / "domain.pddl", PDDL / "pull-in-order.pddl", input="plan\nquit\n", timeout=120)
    assert done.returncode == 0, done.stderr
    assert "pull orange" in done.stdout and done.stdout.index("pull orange") < done.stdout.index("pull yellow")


def test_a_missing_parenthesis_is_placed_in_what_was_typed():
    out = run("type block\npredicate (on ?a - block ?b - block)\nobjects a b - block\ngoal (on a b\n")
    assert "error: the '(' at column 1 of what you typed is never closed: a ')' is missing\n  (on a b\n  ^\n" in out
    out = run("type block\npredicate (far ?b - block)\nobjects a - block\ninit (far a))\n")
    assert "error: unexpected ')' at column 8 of what you typed:\n  (far a))\n         ^" in out


def test_a_domain_with_constants_is_edited_in_the_shell():
    folder = PDDL.parent / "tests" / "data" / "pddl3" / "ipc2006" / "tpp-preferences-qualitative"
    out = run(
        f"load {folder / 'domain.pddl'} {folder / 'instance-1.pddl'}\ngoal (forall (?g - goods) (stored ?g level1))\n"
    )
    assert "(vslsp) goal (forall (?g - goods) (stored ?g level1))\n" in out, out
