"""The commands of ``vslsp shell``: one table read by ``help``, ``vslsp shell --help`` and completion.

A command is added here (usage, what it does, an example) and as a ``do_NAME`` method of
:class:`vslsp.shell.session.Shell`; the help texts and the command completion follow.
This module imports nothing heavy, so that ``vslsp shell --help`` stays fast.
"""

from __future__ import annotations

from typing import NamedTuple


class Command(NamedTuple):
    name: str
    usage: str
    summary: str
    example: str


COMMANDS: tuple[Command, ...] = (
    # --- the domain ---
    Command("domain", "domain NAME", "name the domain", "domain kitchen"),
    Command("type", "type NAME [- PARENT]", "declare a type (under PARENT)", "type cup - dish"),
    Command(
        "predicate",
        "predicate (NAME ?x - TYPE ...)",
        "declare a predicate (again: replace it)",
        "predicate (on-counter ?d - dish)",
    ),
    Command(
        "action",
        "action NAME :parameters (...) :precondition F :effect F",
        "add an action, written as in a domain file (again: replace it)",
        "action pick-up :parameters (?d - dish) :precondition (on-counter ?d) :effect (not (on-counter ?d))",
    ),
    # --- the problem ---
    Command("problem", "problem NAME", "name the problem", "problem tidy-up"),
    Command("objects", "objects NAME ... - TYPE", "add objects of a type", "objects plate bowl - dish"),
    Command("init", "init ATOM ...", "make atoms true in the initial state", "init (on-counter plate) (hand-empty)"),
    Command("goal", "goal FORMULA", "set the goal", "goal (and (clean plate) (clean bowl))"),
    Command(
        "constraint",
        "constraint C",
        "add a PDDL 3.0 trajectory constraint",
        "constraint (sometime-before (clean bowl) (clean plate))",
    ),
    # --- changing what is there ---
    Command(
        "drop",
        "drop action NAME | drop constraint N | drop constraints | drop init ATOM ...",
        "remove an action, constraint N (as `show` numbers them), every constraint, or initial atoms",
        "drop constraint 2",
    ),
    Command("undo", "undo", "take back the last change to the domain or problem (repeat to go further)", "undo"),
    # --- looking, planning, checking ---
    Command(
        "show",
        "show [domain|problem|constraints]",
        "print the PDDL (constraints numbered for `drop constraint N`)",
        "show problem",
    ),
    Command("plan", "plan [PLANNER]", "plan for the problem (fast-downward by default)", "plan"),
    Command(
        "why",
        "why",
        "when the problem has no plan: a minimal set of goal conjuncts and constraints that conflict "
        "(constraints numbered as `show` does)",
        "why",
    ),
    Command(
        "validate",
        "validate [STEP ...]",
        "check the given steps, or the last plan, against preconditions, goal and constraints",
        "validate (pick-up plate) (wash plate)",
    ),
    # --- files ---
    Command(
        "load", "load DOMAIN [PROBLEM]", "read PDDL files (replacing what is in the shell)", "load domain.pddl p.pddl"
    ),
    Command(
        "save",
        "save DOMAIN [PROBLEM]",
        "write PDDL files (after load: the loaded text, comments kept, only the changes rewritten)",
        "save domain.pddl p.pddl",
    ),
    Command("help", "help [COMMAND]", "list the commands, or tell one in full", "help drop"),
    Command("quit", "quit", "leave the shell (also Ctrl-D; Ctrl-C only clears the line)", "quit"),
)

NAMES = tuple(c.name for c in COMMANDS)


def command(name: str) -> Command | None:
    return next((c for c in COMMANDS if c.name == name), None)


def usage(name: str) -> str:
    """``usage: ...`` of the command ``name`` (one of :data:`NAMES`)."""
    return f"usage: {COMMANDS[NAMES.index(name)].usage}"


def example(name: str) -> str:
    return COMMANDS[NAMES.index(name)].example


def overview() -> str:
    """Every command with an example, one per line pair (``help`` and ``vslsp shell --help``)."""
    width = max(len(c.name) for c in COMMANDS)
    return "\n".join(f"  {c.name:<{width}}  {c.summary}\n  {'':<{width}}  e.g. {c.example}" for c in COMMANDS)


def in_full(entry: Command) -> str:
    return f"{entry.usage}\n  {entry.summary}\n  e.g. {entry.example}"
