"""The budget of every phase of work on PDDL input, and the size limits that keep each phase bounded.

A file that is small on disk can still ask for unbounded work: ``(and`` nested 10^5 deep, a type
chain 20 000 deep, a constraint quantified over three variables of 300 objects (27 million
instances). Every phase (reading, checking, grounding, validating) therefore runs within
:data:`PHASE_BUDGET_S` seconds of its own (:func:`phase`), and what grows with the input is bounded
before the work that it would take starts: nesting (:data:`MAX_NESTING` in the language engine,
:data:`MAX_READER_NESTING` on the path through unified-planning's reader, which recurses per level),
the depth of the type hierarchy (:data:`MAX_TYPE_DEPTH`; :data:`MAX_READER_TYPE_DEPTH` on the
reader's path; computed without recursion, :func:`type_depths`), the number of ground instances
(:data:`MAX_GROUND_INSTANCES`, counted before any is built, :func:`check_instances`) and the
did-you-mean's comparisons (:data:`MAX_SUGGESTION_COMPARISONS`). Each limit is said in its own
message, with what to do (docs/bad-input.md, "Deep and huge PDDL").
"""

from __future__ import annotations

import math
import signal
import sys
import threading
from collections.abc import Iterable, Iterator, Mapping
from contextlib import contextmanager

from vslsp.errors import InputError
from vslsp.interrupts import alarm

#: The longest any one phase (reading, checking, grounding, validating) may take, in seconds of wall clock.
PHASE_BUDGET_S = 60.0
#: The deepest parenthesis nesting the language engine reads (its checks recurse once or twice per level).
MAX_NESTING = 1000
#: The deepest nesting sent to unified-planning's reader and planners, which recurse several frames per level.
MAX_READER_NESTING = 40
#: The longest chain of types from a type up to ``object`` that the language engine reads.
MAX_TYPE_DEPTH = 1000
#: The same on the path through unified-planning's reader, which recurses per type (1000 overflow it).
MAX_READER_TYPE_DEPTH = 500
#: The most ground instances of one quantified formula or constraint that vslsp writes out.
MAX_GROUND_INSTANCES = 200_000
#: The most names one check compares for its did-you-mean suggestions (past it, errors come without one:
#: 20 000 unknown names among 20 000 objects would be 4*10^8 comparisons).
MAX_SUGGESTION_COMPARISONS = 2_000_000

#: What to do when a phase runs out of time, by phase.
_ADVICE = {
    "reading": "the file is too large for vslsp's reader (plan with Fast Downward directly)",
    "checking": "the file is too large for vslsp's checker; split it",
    "grounding": "the problem has too many instances for vslsp; use fewer objects or quantified variables",
    "validating": "the plan and the problem are too large to validate within vslsp's budget; shorten the plan",
}


class OverBudget(BaseException):
    """A phase's time is spent (a BaseException: an ``except Exception`` in the libraries a phase calls,
    pyparsing's included, cannot keep it)."""


_active = threading.local()


@contextmanager
def time_budget(seconds: float) -> Iterator[None]:
    """Raise :class:`OverBudget` in the main thread after ``seconds`` (elsewhere, and inside another
    budget, which then governs: no limit of its own)."""
    if (
        threading.current_thread() is not threading.main_thread()
        or not hasattr(signal, "setitimer")
        or getattr(_active, "on", False)
    ):
        yield
        return

    # Once spent, the alarm repeats every 50 ms, and a block that ends after it fired is over budget
    # even if no raise got out (vslsp.interrupts.alarm).
    _active.on = True
    try:
        with alarm(seconds, OverBudget, 0.05):
            yield
    finally:
        _active.on = False


@contextmanager
def phase(what: str, name: str, seconds: float | None = None) -> Iterator[None]:
    """At most ``seconds`` (default :data:`PHASE_BUDGET_S`) for the phase ``what`` (reading, checking,
    grounding, validating) of the input ``name``, else InputError ``NAME: WHAT took more than N s ...``."""
    limit = PHASE_BUDGET_S if seconds is None else seconds
    try:
        with time_budget(limit):
            yield
    except OverBudget:
        raise InputError(
            f"{name}: {what} took more than {limit:g} s and was stopped; {_ADVICE.get(what, 'make the input smaller')}"
        ) from None


#: Python frames the language engine's checks take per level of nesting, at most (a formula inside an
#: unknown predicate's list: the atom, then the formula).
FRAMES_PER_LEVEL = 4


@contextmanager
def recursion_room(levels: int = MAX_NESTING) -> Iterator[None]:
    """Python's recursion limit raised, for the block, to leave room for ``levels`` levels of nesting
    above the frames already in use. Python 3.11 runs a call of Python code without a C frame, so the
    limit, not the thread's stack, is what bounds it."""
    previous = sys.getrecursionlimit()
    sys.setrecursionlimit(max(previous, previous + levels * FRAMES_PER_LEVEL))
    try:
        yield
    finally:
        sys.setrecursionlimit(previous)


def nested_too_deeply(depth: int, limit: int, where: str = "") -> str:
    """The message for parentheses nested ``depth`` deep where ``limit`` levels are read."""
    place = f"{where}: " if where else ""
    return (
        f"{place}parentheses nest {depth} deep here: nested too deeply (limit {limit}); "
        "flatten the formula: (and a (and b c)) is (and a b c)"
    )


def type_depths(parents: Mapping[str, Iterable[str]]) -> dict[str, int]:
    """The depth of every type below ``object`` (``object`` 0, its children 1, ...), by the longest chain of
    parents, in time linear in the hierarchy and without recursion; a type on a cycle, or above one, counts
    the cycle once (cycles are reported apart)."""
    depths: dict[str, int] = {}
    for start in parents:
        if start in depths:
            continue
        path: list[str] = []
        on_path: set[str] = set()
        stack: list[tuple[str, Iterator[str]]] = [(start, iter(parents.get(start, ())))]
        path.append(start)
        on_path.add(start)
        best: dict[str, int] = {start: 0}
        while stack:
            node, pending = stack[-1]
            parent = next(pending, None)
            if parent is None:
                stack.pop()
                path.pop()
                on_path.discard(node)
                depths[node] = best[node] + 1
                if stack:
                    child = stack[-1][0]
                    best[child] = max(best[child], depths[node])
                continue
            if parent == "object" or parent in on_path:
                continue
            if parent in depths:
                best[node] = max(best[node], depths[parent])
                continue
            best[parent] = 0
            stack.append((parent, iter(parents.get(parent, ()))))
            path.append(parent)
            on_path.add(parent)
    return depths


def instance_count(variables: Iterable[tuple[str, str]], universe: Mapping[str, Iterable[str]]) -> int:
    """How many bindings of ``variables`` (``(("?x", "block"), ...)``) over ``universe`` there are."""
    return math.prod(len(tuple(universe.get(type_, ()))) for _, type_ in variables)


def check_instances(count: int, what: str) -> None:
    """InputError when ``count`` instances of ``what`` would be more than :data:`MAX_GROUND_INSTANCES`."""
    if count > MAX_GROUND_INSTANCES:
        raise InputError(
            f"{what} has {count:,} ground instances; vslsp writes out at most {MAX_GROUND_INSTANCES:,} "
            "(too many instances): use fewer objects or fewer quantified variables"
        )
