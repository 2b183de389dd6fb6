"""PDDL 3.0 trajectory constraints judged state by state, keeping no trajectory.

Paper: "Implementation" (the demonstrated order as a constraint the plan must keep). The semantics
are Gerevini & Long's (2005) over the states s_0 .. s_n of a plan; each constraint keeps only what its
verdict still depends on, so validating a plan of n steps takes memory for one state and a few
numbers per constraint, never the n + 1 states:

- ``(always φ)``: the first i with φ false; ``(sometime φ)``: whether φ held; ``(at end φ)``: φ in s_n;
- ``(at-most-once φ)``: the start of the second stretch of states where φ holds;
- ``(sometime-before p q)``: the first i with p and no q in s_0 .. s_(i-1);
- ``(sometime-after p q)``: the first i with p and no q in s_i .. s_n: the first p after the last q.
"""

from __future__ import annotations

from collections.abc import Callable, Collection

from vslsp.symbolic.model.formula import (
    Always,
    AtEnd,
    AtMostOnce,
    Constraint,
    Formula,
    Sometime,
    SometimeAfter,
    SometimeBefore,
    Universe,
    holds,
)


class ConstraintMonitor:
    """One constraint watched over a trajectory: :meth:`observe` each state s_0, s_1, ... in turn, then
    :meth:`verdict` gives where (the state's index) and why it is broken, or None."""

    def __init__(self, constraint: Constraint, universe: Universe) -> None:
        self.constraint = constraint
        self.universe = universe
        self.index = -1  # the last state observed
        self.broken_at: int | None = None  # where a prefix already decided it is broken
        self.held = False  # sometime: φ has held; at-most-once: φ held in the last state; before: q has held
        self.pending: int | None = None  # sometime-after: the first p since the last q
        self.last = False  # at end: φ in the last state observed

    def _holds(self, formula: Formula, state: Collection) -> bool:
        return holds(formula, state, self.universe)  # type: ignore[arg-type]

    def observe(self, state: Collection) -> None:
        """Take the next state of the trajectory (any collection of the atoms that hold)."""
        self.index += 1
        c, i = self.constraint, self.index
        if self.broken_at is not None and not isinstance(c, (AtEnd, Sometime, SometimeAfter)):
            return  # decided
        if isinstance(c, Always):
            if not self._holds(c.formula, state):
                self.broken_at = i
        elif isinstance(c, Sometime):
            self.held = self.held or self._holds(c.formula, state)
        elif isinstance(c, AtEnd):
            self.last = self._holds(c.formula, state)
        elif isinstance(c, AtMostOnce):
            value = self._holds(c.formula, state)
            if value and not self.held and self.pending is not None:
                self.broken_at = i  # a second stretch starts
            if value and not self.held and self.pending is None:
                self.pending = i  # the first stretch starts
            self.held = value
        elif isinstance(c, SometimeBefore):
            if self._holds(c.formula, state) and not self.held:
                self.broken_at = i
            self.held = self.held or self._holds(c.before, state)
        else:
            assert isinstance(c, SometimeAfter)
            if self._holds(c.after, state):
                self.pending = None
            elif self.pending is None and self._holds(c.formula, state):
                self.pending = i

    def verdict(self, when: Callable[[int], str]) -> tuple[int, str] | None:
        """Where and why the constraint is broken on the states observed (``when(i)`` tells state i in
        words), or None."""
        c, last = self.constraint, self.index
        if isinstance(c, Always):
            if self.broken_at is None:
                return None
            return self.broken_at, f"{c.formula.to_pddl()} is false {when(self.broken_at)}"
        if isinstance(c, Sometime):
            return None if self.held else (last, f"{c.formula.to_pddl()} never holds")
        if isinstance(c, AtEnd):
            return None if self.last else (last, f"{c.formula.to_pddl()} is false at the end")
        if isinstance(c, AtMostOnce):
            if self.broken_at is None:
                return None
            return self.broken_at, f"{c.formula.to_pddl()} becomes true again {when(self.broken_at)}"
        if isinstance(c, SometimeBefore):
            if self.broken_at is None:
                return None
            return self.broken_at, (
                f"{c.formula.to_pddl()} holds {when(self.broken_at)} but {c.before.to_pddl()} has not held before"
            )
        assert isinstance(c, SometimeAfter)
        if self.pending is None:
            return None
        return self.pending, (
            f"{c.formula.to_pddl()} holds {when(self.pending)} but {c.after.to_pddl()} never holds then or later"
        )
