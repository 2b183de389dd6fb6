"""Constraints judged state by state give the verdict of PDDL 3.0's semantics over the whole trajectory
(Gerevini & Long 2005), written here over the lists of truth values: every trajectory of up to six
states of two atoms p and q, and the place where each constraint breaks."""

from __future__ import annotations

import itertools

import pytest

from vslsp.symbolic.model.formula import Always, AtEnd, AtMostOnce, Atom, Sometime, SometimeAfter, SometimeBefore
from vslsp.symbolic.validation.monitors import ConstraintMonitor

P, Q = Atom("p", ()), Atom("q", ())


def reference(kind: type, p: list[bool], q: list[bool]) -> int | None:
    """Where the constraint breaks on the trajectory (p_i, q_i), from the definitions; None: it holds."""
    last = len(p) - 1
    if kind is Always:
        return None if all(p) else p.index(False)
    if kind is Sometime:
        return None if any(p) else last
    if kind is AtEnd:
        return None if p[-1] else last
    if kind is AtMostOnce:
        starts = [i for i, v in enumerate(p) if v and (i == 0 or not p[i - 1])]
        return starts[1] if len(starts) > 1 else None
    if kind is SometimeBefore:
        return next((i for i in range(len(p)) if p[i] and not any(q[:i])), None)
    return next((i for i in range(len(p)) if p[i] and not any(q[i:])), None)


def trajectories(length: int):
    for values in itertools.product((False, True), repeat=2 * length):
        yield list(values[:length]), list(values[length:])


@pytest.mark.parametrize("kind", [Always, Sometime, AtEnd, AtMostOnce, SometimeBefore, SometimeAfter])
def test_every_short_trajectory_is_judged_as_the_definition_says(kind):
    constraint = kind(P, Q) if kind in (SometimeBefore, SometimeAfter) else kind(P)
    for length in range(1, 7):
        for p, q in trajectories(length):
            monitor = ConstraintMonitor(constraint, {})
            for p_i, q_i in zip(p, q, strict=True):
                monitor.observe({atom for atom, value in ((P, p_i), (Q, q_i)) if value})
            verdict = monitor.verdict(lambda i: f"in state {i}")
            assert (verdict[0] if verdict else None) == reference(kind, p, q), (kind.__name__, p, q)
