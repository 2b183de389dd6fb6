"""A flat problem read from the language engine's tree is the problem unified-planning's reader gives:
the same objects, initial state and goal, for the shipped problems, the IPC problems of tests/data
without their constraints and metric, and the edge cases of the form; anything else goes to the reader."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from helpers.cli import REPO

from vslsp.symbolic.io import pddl
from vslsp.symbolic.io.flat_problem import flat_problem

DOMAIN = REPO / "pddl" / "domain.pddl"
DATA = REPO / "tests" / "data" / "pddl3"


def without_sections(text: str, *keywords: str) -> str:
    """``text`` with each ``(:keyword ...)`` list removed (comments first)."""
    text = re.sub(r";[^\n]*", "", text)
    for keyword in keywords:
        while (match := re.search(rf"\(\s*{re.escape(keyword)}\b", text, re.IGNORECASE)) is not None:
            depth, end = 0, match.start()
            for end in range(match.start(), len(text)):
                depth += {"(": 1, ")": -1}.get(text[end], 0)
                if depth == 0:
                    break
            text = text[: match.start()] + text[end + 1 :]
    return text


def both_ways(monkeypatch: pytest.MonkeyPatch, domain: Path, problem_text: str, tmp_path: Path):
    """(the problem read as vslsp reads it, the problem unified-planning's reader gives, flat or not)."""
    path = tmp_path / "problem.pddl"
    path.write_text(problem_text)
    fast = pddl.read_pddl(domain, path)[1]
    with monkeypatch.context() as patched:
        patched.setattr(pddl, "flat_problem", lambda *args: None)
        reader = pddl.read_pddl(domain, path)[1]
    return fast, reader


def is_flat(domain: Path, problem_text: str) -> bool:
    parsed = pddl.read_pddl(domain)[0]
    return flat_problem(parsed, domain.read_text(), problem_text) is not None


def cases() -> list[tuple[Path, Path]]:
    found = [(DOMAIN, REPO / "pddl" / name) for name in ("simple-push-pull.pddl", "keep-all-near.pddl")]
    for domain in sorted(DATA.rglob("domain.pddl")):
        found.extend((domain, problem) for problem in sorted(domain.parent.glob("*.pddl")) if problem != domain)
    return found


def marked(pairs: list[tuple[Path, Path]]) -> list:
    """The shipped problems at once; the IPC ones (a minute, read twice each) with the slow tests."""
    return [pytest.param(d, p, marks=[pytest.mark.slow] if DATA in p.parents else []) for d, p in pairs]


@pytest.mark.filterwarnings("ignore")
@pytest.mark.parametrize("domain, problem", marked(cases()), ids=lambda p: "/".join(p.parts[-2:]))
def test_a_flat_problem_reads_as_unified_plannings_reader_reads_it(monkeypatch, tmp_path, domain, problem):
    text = without_sections(problem.read_text(), ":constraints", ":metric")
    fast, reader = both_ways(monkeypatch, domain, text, tmp_path)
    assert fast == reader


@pytest.mark.slow
@pytest.mark.filterwarnings("ignore")
def test_the_ipc_problems_without_constraints_are_mostly_flat():
    flat = [p for d, p in cases() if is_flat(d, without_sections(p.read_text(), ":constraints", ":metric"))]
    assert len(flat) >= 20, flat


EDGES = {
    "negative-and-duplicates": "(:objects a b - block) (:init (far a)) (:goal (and (far b) (not (far a)) (far b)))",
    "one-literal": "(:objects a - block) (:init) (:goal (not (far a)))",
    "empty-goal": "(:objects a - block) (:init (far a)) (:goal (and))",
    "upper-case": "(:objects A B - BLOCK) (:init (FAR A)) (:goal (AND (FAR B)))",
    "no-objects": "(:init) (:goal (and))",
}


@pytest.mark.parametrize("body", EDGES.values(), ids=EDGES.keys())
def test_the_edges_of_the_form_read_alike(monkeypatch, tmp_path, body):
    text = f"(define (problem p) (:domain vsl-sp) {body})"
    assert is_flat(DOMAIN, text)
    fast, reader = both_ways(monkeypatch, DOMAIN, text, tmp_path)
    assert fast == reader


NOT_FLAT = {
    "quantified-goal": "(:objects a - block) (:init) (:goal (forall (?b - block) (far ?b)))",
    "constraints": "(:objects a - block) (:init) (:goal (far a)) (:constraints (always (far a)))",
    "nested-and": "(:objects a - block) (:init) (:goal (and (and (far a))))",
    "or": "(:objects a - block) (:init) (:goal (or (far a)))",
    "object-named-as-predicate": "(:objects far - block) (:init) (:goal (far far))",
    "error": "(:objects a - block) (:init) (:goal (near a))",
}


@pytest.mark.parametrize("body", NOT_FLAT.values(), ids=NOT_FLAT.keys())
def test_any_other_problem_goes_to_the_reader(body):
    assert not is_flat(DOMAIN, f"(define (problem p) (:domain vsl-sp) {body})")
