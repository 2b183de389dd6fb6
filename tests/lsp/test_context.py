"""Where the cursor is, read from the text before it (half-typed files are the normal case)."""

import pytest

from vslsp.lsp.context import (
    ACTION,
    ARGUMENT,
    NOTHING,
    PREDICATE,
    REQUIREMENT,
    SECTION,
    TYPE,
    cursor_at,
    plan_cursor_at,
)


def _cursor(text: str, plan: bool = False):
    return (plan_cursor_at if plan else cursor_at)(text.replace("|", ""), text.index("|"))


@pytest.mark.parametrize(
    ("text", "want", "prefix", "formula"),
    [
        ("(define (domain d)\n  (:requirements :strips :typ|", REQUIREMENT, ":typ", ""),
        ("(define (domain d)\n  (:types a b - |", TYPE, "", ""),
        ("(define (domain d)\n  (:predicates (p ?x - c|", TYPE, "c", ""),
        ("(define (domain d)\n  (:action go :parameters (?x - a ?y - |", TYPE, "", ""),
        (
            "(define (domain d)\n  (:action go :parameters (?x) :precondition (and (p ?x) (on-t|",
            PREDICATE,
            "on-t",
            "goal",
        ),
        ("(define (domain d)\n  (:action go :parameters (?x) :effect (and (not (|", PREDICATE, "", "effect"),
        ("(define (domain d)\n  (:action go :parameters (?x) :precondition (p ?|", ARGUMENT, "?", "goal"),
        ("(define (domain d)\n  (:action go :parameters (?x) :precondition (forall (?y - |", TYPE, "", "goal"),
        ("(define (domain d)\n  (:action go :|", "action-keyword", ":", ""),
        ("(define (domain d)\n  (:|", SECTION, ":", ""),
        ("(define (problem q) (:domain d)\n  (:init (p |", ARGUMENT, "", "init"),
        (
            "(define (problem q) (:domain d)\n  (:constraints (and (sometime-bef|",
            PREDICATE,
            "sometime-bef",
            "constraints",
        ),
        ("(define (problem q) (:domain d)\n  (:goal (and (p a) ; (|", NOTHING, "", ""),
        ("(define (problem q) (:domain d)\n  (:objects a b - |", TYPE, "", ""),
        ("(define (problem q) (:domain d)\n  (:objects a|", NOTHING, "a", ""),
    ],
)
def test_the_context_at_the_cursor(text: str, want: str, prefix: str, formula: str):
    cursor = _cursor(text)
    assert (cursor.want, cursor.prefix, cursor.formula) == (want, prefix, formula)


def test_an_argument_knows_its_atom_and_position():
    cursor = _cursor("(define (problem q)\n  (:init (on-counter mug) (at cup t|")
    assert (cursor.want, cursor.atom, cursor.position, cursor.prefix) == (ARGUMENT, "at", 1, "t")


def test_a_closed_list_is_left_behind():
    cursor = _cursor("(define (domain d)\n  (:types a - b)\n  (:predicates (p) (q)) |")
    assert cursor.want == NOTHING and cursor.heads == ("define",)


@pytest.mark.parametrize(
    ("text", "want", "atom", "position"),
    [
        ("(pick mug)\n(wa|", ACTION, "", 0),
        ("0: (pick mug)\n1: (|", ACTION, "", 0),
        ("1. pick mug\n2. wash m|", ARGUMENT, "wash", 0),
        ("(put-down mug |", ARGUMENT, "put-down", 1),
    ],
)
def test_the_context_in_a_plan(text: str, want: str, atom: str, position: int):
    cursor = _cursor(text, plan=True)
    assert (cursor.want, cursor.atom, cursor.position) == (want, atom, position)
