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


def diagnostics(domain: str, problem: str | None = None) -> list[tuple[int, int, str, str | None]]:
    analysis = analyse(domain, "domain.pddl", problem, "problem.pddl")
    return [(d.line, d.column, d.message, d.suggestion) for d in analysis.diagnostics]


def test_a_correct_domain_and_problem_check_clean():
    assert diagnostics(KITCHEN, DINNER) == []


@pytest.mark.parametrize(
    ("where", "old", "new", "expected"),
    [
        (
            "domain",
            "(and (hand-empty) (on",
            "(and (hand-emty) (on",
            (13, 25, "unknown predicate 'hand-emty'", "hand-empty"),
        ),
        (
            "domain",
            ":precondition (holding ?d)",
            ":precondition (claen ?d)",
            (17, 20, "unknown predicate 'claen'", "clean"),
        ),
        (
            "problem",
            "(sometime-before (clean",
            "(sometimes-before (clean",
            (6, 18, "unknown PDDL 3 operator 'sometimes-before'", "sometime-before"),
        ),
        ("problem", "(on-counter cup))", "(on-counter cupp))", (4, 54, "unknown object or constant 'cupp'", "cup")),
    ],
)
def test_a_typo_is_reported_where_written_with_the_name_meant(where, old, new, expected):
    domain, problem = KITCHEN, DINNER
    if where == "domain":
        domain = domain.replace(old, new, 1)
    else:
        problem = problem.replace(old, new, 1)
    assert diagnostics(domain, problem) == [expected]


def test_the_shipped_domains_and_the_public_corpus_check_without_errors():
    pairs = [(PDDL / "domain.pddl", p) for p in sorted(PDDL.glob("*.pddl")) if p.name != "domain.pddl"]
    corpus = Path(__file__).parents[1] / "data" / "pddl3"
    for domain in sorted(corpus.glob("*/*/domain.pddl")):
        pairs.extend((domain, p) for p in sorted(domain.parent.glob("*.pddl")) if p.name != "domain.pddl")
    assert len(pairs) >= 60
    for domain, problem in pairs:
        errors = [d.format() for d in check_files(domain, problem).errors]
        assert errors == [], (domain, problem)
