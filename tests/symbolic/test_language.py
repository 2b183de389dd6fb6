"""The PDDL language engine (vslsp/symbolic/language): every mistake of a domain and its problem
in one pass, each at the token written, with the declared name closest to an unknown one."""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers.symbolic import PDDL

from vslsp.symbolic.language import analyse, check_files

KITCHEN = """; A kitchen: dishes to clean and put away.
(define (domain kitchen)
  (:requirements :strips :typing :negative-preconditions :constraints)
  (:types dish sponge)
  (:predicates
    ; the robot holds nothing
    (hand-empty)
    (holding ?d - dish)
    (clean ?d - dish)
    (on-counter ?d - dish))
  ; take a dish from the counter
  (:action pick
    :parameters (?d - dish)
    :precondition (and (hand-empty) (on-counter ?d))
    :effect (and (holding ?d) (not (hand-empty)) (not (on-counter ?d))))
  (:action wash
    :parameters (?d - dish ?s - sponge)
    :precondition (holding ?d)
    :effect (clean ?d)))
"""
DINNER = """(define (problem dinner)
  (:domain kitchen)
  (:objects plate cup - dish s - sponge)
  (:init (hand-empty) (on-counter plate) (on-counter cup))
  (:goal (and (clean plate) (clean cup)))
  (:constraints (sometime-before (clean cup) (clean plate))))
"""


def at(text: str, snippet: str, skip: int = 0) -> tuple[int, int]:
    """The 1-based (line, column) of ``snippet``'s first occurrence in ``text``, ``skip`` characters on."""
    index = text.index(snippet) + skip
    return text.count("\n", 0, index) + 1, index - (text.rfind("\n", 0, index) + 1) + 1


def found(domain: str, problem: str | None = None) -> list[tuple[str, int, int, str, str | None]]:
    """(file, line, column, "severity: message", suggestion) of every diagnostic."""
    analysis = analyse(domain, "domain.pddl", problem, "problem.pddl")
    return [(d.file, d.line, d.column, f"{d.severity}: {d.message}", d.suggestion) for d in analysis.diagnostics]


def test_a_correct_domain_and_problem_check_clean():
    assert found(KITCHEN, DINNER) == []


@pytest.mark.parametrize(
    ("in_problem", "old", "new", "message", "suggestion"),
    [
        (False, "(and (hand-empty) (on", "(and (hand-emty) (on", "unknown predicate 'hand-emty'", "hand-empty"),
        (True, "(:init (hand-empty)", "(:init (hand-emty)", "unknown predicate 'hand-emty'", "hand-empty"),
        (False, ":precondition (holding ?d)", ":precondition (claen ?d)", "unknown predicate 'claen'", "clean"),
        (
            True,
            "(sometime-before (clean",
            "(sometimes-before (clean",
            "unknown PDDL 3 operator 'sometimes-before'",
            "sometime-before",
        ),
        (True, "(on-counter cup))", "(on-counter cupp))", "unknown object or constant 'cupp'", "cup"),
        (False, ":negative-preconditions", ":negative-precondition", "unknown requirement", ":negative-preconditions"),
        (False, "(?d - dish ?s - sponge)", "(?d - dsh ?s - sponge)", "undefined type 'dsh'", "dish"),
        (False, ":effect (and (holding ?d)", ":effect (and (holding ?x)", "undefined parameter '?x'", "?d"),
        (False, ":precondition (holding ?d)", ":precondtion (holding ?d)", "unknown keyword", ":precondition"),
        (False, "(and (hand-empty) (on", "(nad (hand-empty) (on", "unknown operator 'nad'", "and"),
    ],
)
def test_a_typo_is_one_error_where_written_with_the_name_meant(in_problem, old, new, message, suggestion):
    domain, problem = KITCHEN, DINNER
    if in_problem:
        problem = problem.replace(old, new, 1)
    else:
        domain = domain.replace(old, new, 1)
    text = problem if in_problem else domain
    typed = next((i for i, (a, b) in enumerate(zip(old, new)) if a != b), min(len(old), len(new)))
    start = new.rfind(" ", 0, typed) + 1
    start = max(start, new.rfind("(", 0, typed) + 1)
    line, column = at(text, new, start)
    [(file, got_line, got_column, got_message, got_suggestion)] = found(domain, problem)
    assert (file, got_line, got_column) == ("problem.pddl" if in_problem else "domain.pddl", line, column)
    assert got_message.startswith(f"error: {message}") and got_suggestion == suggestion


def test_an_undefined_type_is_reported_at_the_type_not_the_variable():
    domain = KITCHEN.replace("(holding ?d - dish)", "(holding ?d - dishh)")
    [(_, line, column, message, suggestion)] = found(domain)
    assert (line, column) == at(domain, "dishh") and message == "error: undefined type 'dishh'" and suggestion == "dish"


def test_a_duplicate_action_is_reported_at_its_second_name():
    domain = KITCHEN.replace("(:action wash", "(:action pick")
    [(_, line, column, message, _)] = found(domain)
    assert (line, column) == (16, 12) and message == "error: action 'pick' is declared twice (first at line 12)"


def test_an_unclosed_parenthesis_is_reported_at_the_parenthesis_that_never_closes():
    problem = DINNER.replace("(on-counter plate)", "(on-counter plate")
    diagnostics = found(KITCHEN, problem)
    assert diagnostics[0][1:4] == (
        *at(problem, "(on-counter plate"),
        "error: '(on-counter' is never closed: a ')' is missing",
    )
    assert len(diagnostics) == 1  # the rest is read as meant: no error after it
    missing_end = DINNER[: DINNER.rindex(")")]
    assert found(KITCHEN, missing_end)[0][1:3] == (1, 1)
    extra = DINNER + ")"
    assert found(KITCHEN, extra)[0][1:4] == (
        7,
        1,
        "error: unexpected ')': there is no '(' left to close; remove it or add the missing '('",
    )


def test_arity_and_argument_types_are_checked():
    problem = DINNER.replace("(clean plate) (clean cup)", "(clean plate cup) (clean s)")
    diagnostics = found(KITCHEN, problem)
    assert [d[1:4] for d in diagnostics] == [
        (*at(problem, "(clean plate cup)"), "error: 'clean' takes 1 argument, 2 given: (clean ?d - dish)"),
        (*at(problem, "(clean s)", 7), "error: 's' is of type sponge, but argument 1 of 'clean' is of type dish"),
    ]


def test_warnings_undeclared_parent_unused_predicate_and_type_undeclared_requirement():
    domain = (
        KITCHEN.replace("(:types dish sponge)", "(:types dish - utensil sponge cloth)")
        .replace("(on-counter ?d - dish))", "(on-counter ?d - dish)\n    (dirty ?d - dish))")
        .replace(":negative-preconditions ", "")
        .replace(":precondition (holding ?d)", ":precondition (and (holding ?d) (not (clean ?d)))")
    )
    diagnostics = found(domain, DINNER)
    assert [d[1:4] for d in diagnostics] == [
        (
            *at(domain, "utensil"),
            "warning: type 'utensil' is used as a parent but not declared; declare it in (:types ...)",
        ),
        (*at(domain, "cloth"), "warning: type 'cloth' is declared but never used in the domain or the problem"),
        (*at(domain, "dirty"), "warning: predicate 'dirty' is declared but never used in the domain or the problem"),
        (
            *at(domain, "(not (clean ?d))", 1),
            "warning: this needs :negative-preconditions, which the domain does not declare in (:requirements ...)",
        ),
    ]


def test_every_error_of_both_files_comes_in_one_run_sorted_by_place():
    domain = KITCHEN.replace("(hand-empty) (on", "(hand-emty) (on").replace("(clean ?d)))", "(claen ?d)))")
    domain = domain.replace("(:action wash", "(:action pick")
    problem = DINNER.replace("(on-counter cup)", "(on-counter cupp)").replace("sometime-before", "sometimes-before")
    diagnostics = found(domain, problem)
    assert [(d[0], d[4]) for d in diagnostics] == [
        ("domain.pddl", "hand-empty"),
        ("domain.pddl", None),  # the second 'pick'
        ("domain.pddl", "clean"),
        ("problem.pddl", "cup"),
        ("problem.pddl", "sometime-before"),
    ]


def test_quick_fixes_replace_the_typo_or_declare_the_missing_name():
    domain = KITCHEN.replace("(and (hand-empty) (on", "(and (hand-emty) (on")
    [diagnostic] = analyse(domain, "domain.pddl").diagnostics
    replace, declare = diagnostic.fixes
    assert replace.text == "hand-empty" and replace.span == diagnostic.span
    assert declare.title == "declare predicate 'hand-emty'" and declare.text == "\n    (hand-emty)"
    assert (declare.span.line, declare.span.column) == at(
        domain, "(on-counter ?d - dish))", len("(on-counter ?d - dish)")
    )


def test_the_index_has_every_declaration_with_its_comment_and_every_reference():
    analysis = analyse(KITCHEN, "domain.pddl", DINNER, "problem.pddl")
    index = analysis.index
    hand_empty = index.find("predicate", "hand-empty")
    assert hand_empty is not None and hand_empty.comment == "the robot holds nothing"
    assert (hand_empty.span.line, hand_empty.span.column) == at(KITCHEN, "hand-empty")
    assert [(r.span.file, r.span.line) for r in index.references_to(hand_empty)] == [
        ("domain.pddl", 14),
        ("domain.pddl", 15),
        ("problem.pddl", 4),
    ]
    pick = index.find("action", "pick")
    assert pick is not None and pick.comment == "take a dish from the counter"
    assert pick.signature == "(:action pick :parameters (?d - dish))"
    plate = index.find("object", "plate")
    assert plate is not None and plate.types == ("dish",) and len(index.references_to(plate)) == 3
    symbol = index.symbol_at("problem.pddl", *at(DINNER, "(clean cup)", 3))
    assert symbol is not None and getattr(symbol, "declaration", None) is index.find("predicate", "clean")
    assert [d.name for d in index.in_file("problem.pddl")] == ["dinner", "plate", "cup", "s"]


def test_the_shipped_domains_and_the_public_corpus_check_without_errors():
    pairs = [(PDDL / "domain.pddl", p) for p in sorted(PDDL.glob("*.pddl")) if p.name != "domain.pddl"]
    corpus = Path(__file__).parents[1] / "data" / "pddl3"
    for domain in sorted(corpus.glob("*/*/domain.pddl")):
        pairs.extend((domain, p) for p in sorted(domain.parent.glob("*.pddl")) if p.name != "domain.pddl")
    assert len(pairs) >= 60
    for domain, problem in pairs:
        errors = [d.format() for d in check_files(domain, problem).errors]
        assert errors == [], (domain, problem)


def test_offsets_count_a_crlf_comments_carriage_return():
    from vslsp.symbolic.language.syntax import read_document

    text = "; a comment\r\n(define (domain d)) ; another\r\n(x)\r\n"
    document = read_document(text, "crlf.pddl")
    for token in document.tokens + document.comments:
        assert text[token.offset : token.offset + len(token.text)] == token.text, token
    assert [c.text for c in document.comments] == ["; a comment", "; another"]
