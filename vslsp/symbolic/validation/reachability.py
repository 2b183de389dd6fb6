"""Why a goal atom can never hold: relaxed reachability (delete effects ignored, negative
conditions taken as satisfiable), which over-approximates what any plan can make true.

When the planner proves that the goal cannot be reached and no constraint takes part
(:mod:`vslsp.symbolic.validation.conflict`), the conflict names the goal conjuncts; this module says why
for each atom that not even the relaxation reaches: which ground actions would add it, and for
each the precondition atom that never holds (and, for an atom no action ever changes, what the
initial state says instead: ``(colour-of r1 red)`` where ``(colour-of r1 green)`` is needed).
An atom that the relaxation reaches, yet no plan does, is unreachable through the interactions
of the actions' deletes: that is said as such, without a cause.

The fixpoint grounds every action over the problem's objects; above :data:`MAX_INSTANCES`
ground actions no reason is given (the conflict alone stands).
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from math import prod

from vslsp.symbolic.model.domain import Action, Domain, Problem, When
from vslsp.symbolic.model.formula import (
    And,
    Atom,
    Equals,
    Forall,
    Formula,
    Imply,
    Not,
    Or,
    Universe,
    bindings,
    substitute,
)

MAX_INSTANCES = 20_000  # ground actions: beyond, the relaxation is not computed
_SHOWN = 3  # ground actions that would add an atom, shown per atom


@dataclass(frozen=True)
class Reach:
    """The atoms the relaxation reaches from the initial state, and the ground actions it applies."""

    reached: frozenset
    universe: Universe


def relaxed_reach(domain: Domain, problem: Problem) -> Reach | None:
    """The relaxed fixpoint of ``problem``, or None when it has more than :data:`MAX_INSTANCES`
    ground actions."""
    universe = problem.universe()
    count = sum(prod(len(universe.get(t, ())) for _, t in action.parameters) for action in domain.actions)
    if count > MAX_INSTANCES:
        return None
    instances = [
        (substitute(a.precondition, b), a, b) for a in domain.actions for b in bindings(a.parameters, universe)
    ]
    reached = set(problem.init)
    changed = True
    while changed:  # every pass applies each applicable action (a conditional effect may add more later)
        before = len(reached)
        for precondition, action, binding in instances:
            if relaxed_holds(precondition, reached, universe):
                reached.update(_relaxed_adds(action, binding, reached, universe))
        changed = len(reached) > before
    return Reach(frozenset(reached), universe)


def relaxed_holds(formula: Formula, reached: set | frozenset, universe: Universe) -> bool:
    """Whether ground ``formula`` may hold once ``reached`` atoms have held (negations optimistic)."""
    if isinstance(formula, Atom):
        return formula in reached
    if isinstance(formula, (Equals, Not)):
        return formula.left == formula.right if isinstance(formula, Equals) else True
    if isinstance(formula, And):
        return all(relaxed_holds(a, reached, universe) for a in formula.args)
    if isinstance(formula, Or):
        return any(relaxed_holds(a, reached, universe) for a in formula.args)
    if isinstance(formula, Imply):
        return True  # the condition may be false
    parts = (
        relaxed_holds(substitute(formula.body, b), reached, universe) for b in bindings(formula.variables, universe)
    )
    return all(parts) if isinstance(formula, Forall) else any(parts)


def _relaxed_adds(action: Action, binding: dict, reached: set, universe: Universe) -> Iterator[Atom]:
    for effect in action.effects:
        if isinstance(effect, Atom):
            yield substitute(effect, binding)  # type: ignore[misc]
        elif isinstance(effect, When):
            for extra in bindings(effect.variables, universe):
                local = {**binding, **extra}
                if relaxed_holds(substitute(effect.condition, local), reached, universe):
                    yield from (substitute(e, local) for e in effect.effects if isinstance(e, Atom))  # type: ignore[misc]


def why_never(goal: Formula, domain: Domain, problem: Problem, reach: Reach) -> list[str]:
    """Why each atom of the goal conjunct ``goal`` that the relaxation never reaches cannot hold:
    one line per atom; [] when every atom of it is reached (then deletes are the reason)."""
    lines = []
    for atom in _positive_atoms(goal):
        if atom not in reach.reached:
            lines.append(_why_atom(atom, domain, problem, reach))
    return lines


def _why_atom(atom: Atom, domain: Domain, problem: Problem, reach: Reach) -> str:
    adders = list(_adders(atom, domain, reach.universe))
    if not adders:
        return f"{atom.to_pddl()} can never hold: it is not true initially and no action makes it true"
    shown = []
    for action, binding in adders[:_SHOWN]:
        missing = [p for p in _positive_atoms(substitute(action.precondition, binding)) if p not in reach.reached]
        call = f"({action.name}{''.join(' ' + binding[v] for v, _ in action.parameters)})"
        needs = f" needs {missing[0].to_pddl()}{_never(missing[0], domain, problem)}" if missing else " never runs"
        shown.append(call + needs)
    more = f"; and {len(adders) - _SHOWN} more" if len(adders) > _SHOWN else ""
    some = "the one action" if len(adders) == 1 else f"the {len(adders)} actions"
    return f"{atom.to_pddl()} can never hold: {some} that would make it true cannot run: {'; '.join(shown)}{more}"


def _never(atom: Atom, domain: Domain, problem: Problem) -> str:
    """Why a needed atom never holds, in a few words."""
    if any(a.predicate == atom.predicate for action in domain.actions for a in action.effect_atoms()):
        return ", which no reachable action makes true"
    instead = sorted(
        a.to_pddl()
        for a in problem.init
        if a.predicate == atom.predicate and a.args[:1] == atom.args[:1] and len(a.args) == len(atom.args)
    )
    given = f" ({' '.join(instead)} {'is' if len(instead) == 1 else 'are'})" if instead else ""
    return f", which no action changes and is not true initially{given}"


def _adders(atom: Atom, domain: Domain, universe: Universe) -> Iterator[tuple[Action, dict]]:
    """The ground actions (schema, binding) with an effect that writes ``atom`` true."""
    for action in domain.actions:
        parameters = dict(action.parameters)
        for written in _added_atoms(action):
            if written.predicate != atom.predicate or len(written.args) != len(atom.args):
                continue
            fixed: dict[str, str] | None = {}
            for term, value in zip(written.args, atom.args):
                if term in parameters and fixed is not None:
                    if fixed.setdefault(term, value) != value or value not in universe.get(parameters[term], ()):
                        fixed = None
                elif term != value:
                    fixed = None
            if fixed is None:
                continue
            free = tuple((v, t) for v, t in action.parameters if v not in fixed)
            for rest in bindings(free, universe):
                yield action, {**fixed, **rest}


def _added_atoms(action: Action) -> Iterable[Atom]:
    for effect in action.effects:
        if isinstance(effect, Atom):
            yield effect
        elif isinstance(effect, When):
            yield from (e for e in effect.effects if isinstance(e, Atom))


def _positive_atoms(formula: Formula) -> list[Atom]:
    """The atoms a conjunction asks to be true (its positive conjuncts)."""
    if isinstance(formula, Atom):
        return [formula]
    if isinstance(formula, And):
        return [a for part in formula.args for a in _positive_atoms(part)]
    return []


__all__ = ["MAX_INSTANCES", "Reach", "relaxed_holds", "relaxed_reach", "why_never"]
