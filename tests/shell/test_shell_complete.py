"""Tab completion in ``vslsp shell``: what fits where the cursor is, hyphenated names whole."""

import pytest
from helpers.symbolic import PDDL

from vslsp.shell.commands import NAMES
from vslsp.shell.complete import DELIMITERS
from vslsp.shell.session import Shell
from vslsp.symbolic import read_pddl


@pytest.fixture(scope="module")
def kitchen() -> Shell:
    shell = Shell()
    for line in (
        "type dish",
        "type cup - dish",
        "type cloth",
        "predicate (on-counter ?d - dish)",
        "predicate (on-shelf ?d - dish)",
        "predicate (hand-empty)",
        "predicate (wiped ?d - dish ?c - cloth)",
        "action pick-up :parameters (?d - dish) :precondition (on-counter ?d) :effect (not (on-counter ?d))",
        "action put-on-shelf :parameters (?d - dish) :precondition (hand-empty) :effect (on-shelf ?d)",
        "objects plate bowl - dish",
        "objects mug - cup",
        "objects rag - cloth",
        "init (on-counter plate) (on-counter mug)",
        "constraint (sometime-before (on-shelf mug) (on-shelf plate))",
        "constraint (always (hand-empty))",
    ):
        shell.onecmd(line)
    assert len(shell.problem.constraints) == 2, "the set-up failed"
    return shell


def completions(shell: Shell, line: str) -> list[str]:
    """What TAB offers at the end of ``line``, the word split as readline splits it."""
    begidx = max(line.rfind(d) for d in DELIMITERS) + 1
    text = line[begidx:]
    if begidx == 0:
        return shell.completenames(text, line, begidx, len(line))
    return shell.completedefault(text, line, begidx, len(line))


def test_commands_come_first(kitchen):
    assert completions(kitchen, "") == [f"{name} " for name in NAMES]
    assert completions(kitchen, "pr") == ["predicate ", "problem "]
    assert completions(kitchen, "help dr") == ["drop "]


def test_hyphenated_names_complete_whole(kitchen):
    assert "-" not in DELIMITERS and "?" not in DELIMITERS
    assert completions(kitchen, "init (on-") == ["on-counter ", "on-shelf "]
    assert completions(kitchen, "init (on-c") == ["on-counter "]
    assert completions(kitchen, "drop action put-") == ["put-on-shelf "]
    assert completions(kitchen, "goal (hand-") == ["hand-empty "]


def test_predicates_inside_formulas_with_the_connectives_that_fit(kitchen):
    assert completions(kitchen, "init (") == ["hand-empty ", "on-counter ", "on-shelf ", "wiped "]
    goal = completions(kitchen, "goal (and (")
    assert "on-shelf " in goal and "forall " in goal and "when " not in goal
    effect = completions(kitchen, "action wash :parameters (?d - dish) :effect (and (")
    assert "when " in effect and "or " not in effect and "wiped " in effect


def test_types_after_a_dash(kitchen):
    assert completions(kitchen, "predicate (dry ?d - ") == ["cloth ", "cup ", "dish ", "object "]
    assert completions(kitchen, "objects saucer - d") == ["dish "]
    assert completions(kitchen, "type saucer - c") == ["cloth ", "cup "]
    assert completions(kitchen, "action dry :parameters (?d - di") == ["dish "]
    assert completions(kitchen, "goal (forall (?x - c") == ["cloth ", "cup "]
    assert completions(kitchen, "objects sau") == []  # a new name: nothing to offer


def test_objects_of_the_parameters_type(kitchen):
    assert completions(kitchen, "init (on-counter ") == ["bowl ", "mug ", "plate "]
    assert completions(kitchen, "init (wiped plate ") == ["rag "]  # the second parameter is a cloth
    assert completions(kitchen, "goal (on-shelf m") == ["mug "]
    assert completions(kitchen, "validate (pick-up ") == ["bowl ", "mug ", "plate "]
    assert completions(kitchen, "validate (p") == ["pick-up ", "put-on-shelf "]
    assert completions(kitchen, "goal (forall (?x - cup) (on-shelf ") == ["?x ", "bowl ", "mug ", "plate "]


def test_an_actions_variables_and_keywords(kitchen):
    line = "action dry :parameters (?d - dish ?c - cloth) :precondition (wiped "
    assert completions(kitchen, line) == ["?d "]  # its variables of the type (and constants), no objects
    assert completions(kitchen, line + "?d ") == ["?c "]
    assert completions(kitchen, "action dry :parameters (?d - dish) :") == [":effect ", ":precondition "]


def test_pddl3_operators_in_constraints(kitchen):
    operators = completions(kitchen, "constraint (")
    assert "sometime-before " in operators and "at-most-once " in operators and "on-shelf " not in operators
    assert completions(kitchen, "constraint (sometime-b") == ["sometime-before "]
    assert completions(kitchen, "constraint (sometime-before (on-") == ["on-counter ", "on-shelf "]
    assert completions(kitchen, "constraint (at ") == ["end "]


def test_drop(kitchen):
    assert completions(kitchen, "drop ") == ["action ", "constraint ", "constraints ", "init "]
    assert completions(kitchen, "drop constraint ") == ["1 ", "2 "]
    assert completions(kitchen, "drop action ") == ["pick-up ", "put-on-shelf "]
    assert completions(kitchen, "drop init (on-counter p") == ["plate "]
    assert completions(kitchen, "show ") == ["constraints ", "domain ", "problem "]


def test_file_names(kitchen, monkeypatch):
    monkeypatch.chdir(PDDL.parent)
    assert completions(kitchen, "load pddl/dom") == ["pddl/domain.pddl "]
    assert completions(kitchen, "save pdd") == ["pddl/"]


def test_a_loaded_domain_completes_too():
    shell = Shell(*read_pddl(PDDL / "domain.pddl", PDDL / "keep-all-near.pddl"))
    assert completions(shell, "init (f") == ["far "]
    assert "pull " in completions(shell, "validate (pu")
