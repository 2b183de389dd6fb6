"""PDDL 3.0 trajectory constraints compiled into the lifted domain (no grounding in Python).

Paper: "Implementation" (the demonstrated order as ``sometime-before`` constraints handed to
an off-the-shelf planner that has no constraints). The construction follows TCORE (Bonassi,
Gerevini, Percassi, Scala) and its lifted variant LiftedTCORE: every constraint gets
monitoring atoms, and every action schema gets conditional effects that update them. What a
step makes true is computed by *regression* of the constraint's formula through the action's
effects, with equality between the action's parameters and the formula's terms, so the
planner's own grounder (Fast Downward's) instantiates the monitors with the actions:

- ``R(p(t), a) = ∨_{add p(u) if c} (t = u ∧ c)  ∨  p(t) ∧ ¬∨_{del p(v) if c'} (t = v ∧ c')``;
- ``becomes(φ, a) = R(φ, a) ∧ ¬φ``: φ false now, true after ``a``.

With a 0-ary ``violated`` atom (every action requires it false, the goal too):

=======================  ================================================================
``(always φ)``           φ in s_0; ``when becomes(¬φ) -> violated``
``(sometime φ)``         ``hold`` (φ in s_0); ``when becomes(φ) -> hold``; goal ``hold``
``(at-most-once φ)``     ``seen`` (φ in s_0); ``when becomes(φ) -> seen``; ``when becomes(φ) ∧ seen -> violated``
``(sometime-before p q)``  ``hold_q``; ``when becomes(q) -> hold_q``; ``when becomes(p) ∧ ¬hold_q -> violated``
``(sometime-after p q)``   ``ok`` (¬p ∨ q in s_0); ``when R(p) ∧ ¬R(q) -> ¬ok``; ``when R(q) -> ok``; goal ``ok``
``(at end φ)``           goal φ
=======================  ================================================================

An action whose effects touch no predicate of a formula cannot change its truth: it gets no
effect for that formula. Quantifiers inside the formulas stay quantified (the planner
compiles them); a ``forall`` around whole constraints was expanded when the problem was read.
"""

from __future__ import annotations

import itertools
import re
from dataclasses import dataclass, replace

from vslsp.symbolic.model.domain import Action, Domain, Effect, Predicate, Problem, When
from vslsp.symbolic.model.formula import (
    Always,
    And,
    AtEnd,
    AtMostOnce,
    Atom,
    Constraint,
    Equals,
    Exists,
    Forall,
    Formula,
    Imply,
    Not,
    Or,
    Sometime,
    SometimeAfter,
    SometimeBefore,
    Universe,
    atoms_of,
    conjunction,
    constraint_formulas,
    holds,
    substitute,
)

TRUE: Formula = And(())
FALSE: Formula = Or(())
PREFIX = "vslsp-"
VIOLATED = Atom(f"{PREFIX}violated")


def compile_lifted(domain: Domain, problem: Problem) -> tuple[Domain, Problem]:
    """The domain and problem without trajectory constraints, with the same plans (over the original actions).

    Constraints of one shape (the same kind and formulas up to the objects named, e.g. the
    199 ``sometime-before`` of a demonstrated order) share one parameterised monitor
    ``(vslsp-cK ?a ?b)`` over a static relation ``(vslsp-tK ?a ?b)`` listing their objects.
    """
    if not problem.constraints:
        return domain, problem
    fresh = itertools.count(1)
    universe, init = problem.universe(), frozenset(problem.init)
    predicates: list[Predicate] = [Predicate(VIOLATED.predicate)]
    goals: list[Formula] = [problem.goal, Not(VIOLATED)]
    new_init: set[Atom] = set()
    per_action: dict[str, list[Effect]] = {a.name: [] for a in domain.actions}

    for index, (constraint, variables, rows) in enumerate(_templates(problem, fresh), start=1):
        _monitor(
            _Target(domain, init, universe, predicates, goals, new_init, per_action), index, constraint, variables, rows
        )

    actions = tuple(
        replace(
            a,
            precondition=conjunction([a.precondition, Not(VIOLATED)]) if a.precondition != TRUE else Not(VIOLATED),
            effects=(*a.effects, *per_action[a.name]),
        )
        for a in domain.actions
    )
    compiled = replace(domain, predicates=(*domain.predicates, *predicates), actions=actions)
    return compiled, replace(problem, domain=compiled, init=init | new_init, goal=conjunction(goals), constraints=())


@dataclass
class _Target:
    """What the monitors of the constraints add to: predicates, goal parts, initial atoms, effects per action."""

    domain: Domain
    init: frozenset
    universe: Universe
    predicates: list[Predicate]
    goals: list[Formula]
    new_init: set[Atom]
    per_action: dict[str, list[Effect]]


def _monitor(
    target: _Target,
    index: int,
    constraint: Constraint,
    variables: tuple[tuple[str, str], ...],
    rows: list[tuple[str, ...]],
) -> None:
    """The monitor of one constraint (or one shape of constraints, ``variables`` over ``rows``)."""
    domain, init, universe = target.domain, target.init, target.universe
    predicates, goals, new_init, per_action = target.predicates, target.goals, target.new_init, target.per_action
    names = tuple(v for v, _ in variables)
    monitor, relation = Atom(f"{PREFIX}c{index}", names), Atom(f"{PREFIX}t{index}", names)
    if variables:
        predicates.append(Predicate(relation.predicate, variables))
        new_init.update(Atom(relation.predicate, row) for row in rows)

    def add(condition_of, atom: Atom, value: bool = True) -> None:
        """For every action: ``when condition_of(action) -> atom`` (or ``not atom``), for every row."""
        for action in domain.actions:
            condition = condition_of(action)
            if condition == FALSE:
                continue
            effect = (atom if value else Not(atom),)
            if not variables:
                per_action[action.name].append(When(condition, effect))
                continue
            for disjunct in _disjuncts(_and(relation, condition)):
                per_action[action.name].append(_bound(disjunct, effect, variables, action, domain))

    def initially(formula: Formula) -> None:
        """``monitor`` true initially for the rows where ``formula`` holds in s_0."""
        for row in rows:
            if holds(substitute(formula, dict(zip(names, row, strict=False))), init, universe):
                new_init.add(Atom(monitor.predicate, row))

    def goal(formula: Formula) -> None:
        """``formula`` in the goal for every row (written out: the planner's heuristics see each part)."""
        goals.extend(substitute(formula, dict(zip(names, row, strict=False))) for row in rows)

    if not isinstance(constraint, (AtEnd, Always)):
        predicates.append(Predicate(monitor.predicate, variables))
    if isinstance(constraint, AtEnd):
        goal(constraint.formula)
    elif isinstance(constraint, Always):
        phi = constraint.formula
        add(lambda a, phi=phi: becomes(Not(phi), a), VIOLATED)  # type: ignore[misc]
    elif isinstance(constraint, Sometime):
        phi = constraint.formula
        goal(monitor)
        initially(phi)
        add(lambda a, phi=phi: becomes(phi, a), monitor)  # type: ignore[misc]
    elif isinstance(constraint, AtMostOnce):
        phi = constraint.formula
        initially(phi)
        add(lambda a, phi=phi, m=monitor: _and(becomes(phi, a), m), VIOLATED)  # type: ignore[misc]
        add(lambda a, phi=phi: becomes(phi, a), monitor)  # type: ignore[misc]
    elif isinstance(constraint, SometimeBefore):
        p, q = constraint.formula, constraint.before
        initially(q)
        add(lambda a, p=p, m=monitor: _and(becomes(p, a), Not(m)), VIOLATED)  # type: ignore[misc]
        add(lambda a, q=q: becomes(q, a), monitor)  # type: ignore[misc]
    else:
        assert isinstance(constraint, SometimeAfter)
        p, q = constraint.formula, constraint.after
        goal(monitor)
        initially(Imply(p, q))
        add(
            lambda a, p=p, q=q: _and(regress(p, a), _not(regress(q, a))) if _touches(a, p, q) else FALSE,
            monitor,
            value=False,
        )
        add(lambda a, q=q: regress(q, a) if _touches(a, q) else FALSE, monitor)  # type: ignore[misc]


def _templates(problem: Problem, fresh) -> list[tuple[Constraint, tuple[tuple[str, str], ...], list[tuple[str, ...]]]]:
    """The constraints grouped by shape: (the lifted constraint, its typed variables, one row of objects per
    constraint). A shape met once stays ground (no variables, one empty row)."""
    types = dict(problem.all_objects())
    signatures = {p.name: [t for _, t in p.parameters] for p in problem.domain.predicates}
    groups: dict[tuple, tuple[Constraint, tuple[tuple[str, str], ...], list[tuple[str, ...]]]] = {}
    originals: dict[tuple, Constraint] = {}
    for constraint in problem.constraints:
        constraint = _renamed(constraint, fresh)
        objects: dict[str, str] = {}  # object -> its placeholder's type

        for part in constraint_formulas(constraint):
            _collect_objects(part, objects, signatures, types)
        placeholders = {o: f"?{PREFIX}o{i}" for i, o in enumerate(objects)}
        lifted = type(constraint)(*(substitute(f, placeholders) for f in constraint_formulas(constraint)))  # type: ignore[arg-type]
        key = (_canonical(lifted), tuple(objects.values()))
        if key not in groups:
            variables = tuple((placeholders[o], t) for o, t in objects.items())
            groups[key] = (lifted, variables, [])  # type: ignore[assignment]
            originals[key] = constraint
        groups[key][2].append(tuple(objects))
    templates: list[tuple[Constraint, tuple[tuple[str, str], ...], list[tuple[str, ...]]]] = []
    for key, (lifted, variables, rows) in groups.items():
        if len(rows) == 1:
            templates.append((originals[key], (), [()]))
        else:
            templates.append((lifted, variables, rows))
    return templates


def _disjuncts(formula: Formula, limit: int = 16) -> list[Formula]:
    """``formula`` as a disjunction of conjunctions over its and/or structure (as it is if that takes more than
    ``limit`` disjuncts)."""

    def dnf(f: Formula) -> list[list[Formula]]:
        if isinstance(f, Or):
            return [c for a in f.args for c in dnf(a)]
        if isinstance(f, And):
            result: list[list[Formula]] = [[]]
            for a in f.args:
                result = [x + y for x in result for y in dnf(a)]
                if len(result) > limit:
                    raise OverflowError
            return result
        return [[f]]

    try:
        return [_and(*c) for c in dnf(formula)]
    except OverflowError:
        return [formula]


def _bound(
    condition: Formula,
    effect: tuple[Formula, ...],
    variables: tuple[tuple[str, str], ...],
    action: Action,
    domain: Domain,
) -> When:
    """``When(condition, effect, variables)`` with each variable that the condition equates to an action
    parameter (of its type or below) replaced by that parameter: the planner need not range over it."""
    parameters = dict(action.parameters)
    free = dict(variables)
    changed = True
    while changed:
        changed = False
        parts = condition.args if isinstance(condition, And) else (condition,)
        for part in parts:
            if not isinstance(part, Equals):
                continue
            for var, term in ((part.left, part.right), (part.right, part.left)):
                if var in free and term in parameters and parameters[term] in domain.subtypes(free[var]):
                    condition = substitute(condition, {var: term})
                    effect = tuple(substitute(e, {var: term}) for e in effect)
                    del free[var]
                    changed = True
                    break
            if changed:
                break
    condition = _and(
        *(
            p
            for p in (condition.args if isinstance(condition, And) else (condition,))
            if not (isinstance(p, Equals) and p.left == p.right)
        )
    )
    return When(condition, effect, tuple((v, t) for v, t in variables if v in free))


def _collect_objects(
    formula: Formula, objects: dict[str, str], signatures: dict[str, list[str]], types: dict[str, str]
) -> None:
    """Add to ``objects`` (object -> the type of its place) the objects ``formula`` names, in order."""
    if isinstance(formula, Atom):
        for position, arg in enumerate(formula.args):
            if not arg.startswith("?") and arg not in objects:
                objects[arg] = signatures[formula.predicate][position]
    elif isinstance(formula, Equals):
        for arg in (formula.left, formula.right):
            if not arg.startswith("?") and arg not in objects:
                objects[arg] = types.get(arg, "object")
    elif isinstance(formula, Not):
        _collect_objects(formula.arg, objects, signatures, types)
    elif isinstance(formula, (And, Or)):
        for part in formula.args:
            _collect_objects(part, objects, signatures, types)
    elif isinstance(formula, Imply):
        _collect_objects(formula.condition, objects, signatures, types)
        _collect_objects(formula.consequence, objects, signatures, types)
    else:
        _collect_objects(formula.body, objects, signatures, types)


def _canonical(constraint: Constraint) -> str:
    """The constraint's text with quantified variables numbered in order (``?vslsp-N`` differ per constraint)."""
    text = constraint.to_pddl()
    names: dict[str, str] = {}
    return re.sub(rf"\?{PREFIX}\d+\b", lambda m: names.setdefault(m.group(0), f"?q{len(names)}"), text)


def objects_named(domain: Domain) -> set[str]:
    """The objects (not variables) written in the domain's action schemas."""
    names: set[str] = set()

    def terms(formula: Formula) -> None:
        if isinstance(formula, Atom):
            names.update(a for a in formula.args if not a.startswith("?"))
        elif isinstance(formula, Equals):
            names.update(a for a in (formula.left, formula.right) if not a.startswith("?"))
        elif isinstance(formula, Not):
            terms(formula.arg)
        elif isinstance(formula, (And, Or)):
            for part in formula.args:
                terms(part)
        elif isinstance(formula, Imply):
            terms(formula.condition)
            terms(formula.consequence)
        else:
            terms(formula.body)

    for action in domain.actions:
        terms(action.precondition)
        for effect in action.effects:
            if isinstance(effect, When):
                terms(effect.condition)
            for literal_ in effect.effects if isinstance(effect, When) else (effect,):
                terms(literal_)
    return names


def regress(formula: Formula, action: Action) -> Formula:
    """The condition, in the state before ``action``, for ``formula`` to hold after it (lifted)."""
    if isinstance(formula, Atom):
        if formula.predicate == VIOLATED.predicate:
            return formula
        adds, deletes = _writers(formula, action)
        return _or(*adds, _and(formula, _not(_or(*deletes))))
    if isinstance(formula, Equals):
        return formula
    if isinstance(formula, Not):
        return _not(regress(formula.arg, action))
    if isinstance(formula, And):
        return _and(*(regress(a, action) for a in formula.args))
    if isinstance(formula, Or):
        return _or(*(regress(a, action) for a in formula.args))
    if isinstance(formula, Imply):
        return _or(_not(regress(formula.condition, action)), regress(formula.consequence, action))
    body = regress(formula.body, action)
    return type(formula)(formula.variables, body) if body not in (TRUE, FALSE) else body


def becomes(formula: Formula, action: Action) -> Formula:
    """The condition, before ``action``, for ``formula`` to be false now and true after it (FALSE if it cannot)."""
    if not _touches(action, formula):
        return FALSE
    if isinstance(formula, Atom):  # R ∧ ¬p simplified: some add applies and p is false now
        return _and(_or(*_writers(formula, action)[0]), Not(formula))
    if isinstance(formula, Not) and isinstance(formula.arg, Atom):  # p now, deleted and not re-added
        adds, deletes = _writers(formula.arg, action)
        return _and(formula.arg, _or(*deletes), _not(_or(*adds)))
    return _and(regress(formula, action), _not(formula))


def _writers(atom: Atom, action: Action) -> tuple[list[Formula], list[Formula]]:
    """The conditions under which ``action`` adds / deletes ``atom``: one per effect writing its predicate."""
    adds: list[Formula] = []
    deletes: list[Formula] = []
    for effect in action.effects:
        condition, variables = (effect.condition, effect.variables) if isinstance(effect, When) else (TRUE, ())
        for literal_ in effect.effects if isinstance(effect, When) else (effect,):
            positive = not isinstance(literal_, Not)
            written = literal_ if positive else literal_.arg  # type: ignore[union-attr]
            if written.predicate != atom.predicate:  # type: ignore[union-attr]
                continue
            match = _and(*(_equal(t, u) for t, u in zip(atom.args, written.args, strict=False)), condition)  # type: ignore[union-attr]
            if variables and match != FALSE:
                match = Exists(variables, match)
            (adds if positive else deletes).append(match)
    return adds, deletes


def _touches(action: Action, *formulas: Formula) -> bool:
    written = {a.predicate for a in action.effect_atoms()}
    return any(atom.predicate in written for f in formulas for atom in atoms_of(f))


def _renamed(constraint: Constraint, fresh) -> Constraint:
    """``constraint`` with every quantified variable renamed ``?vslsp-N`` (no clash with action parameters)."""

    def rename(formula: Formula) -> Formula:
        if isinstance(formula, (Forall, Exists)):
            names = {v: f"?{PREFIX}{next(fresh)}" for v, _ in formula.variables}
            body = rename(substitute(formula.body, names))
            return type(formula)(tuple((names[v], t) for v, t in formula.variables), body)
        if isinstance(formula, Not):
            return Not(rename(formula.arg))
        if isinstance(formula, (And, Or)):
            return type(formula)(tuple(rename(a) for a in formula.args))
        if isinstance(formula, Imply):
            return Imply(rename(formula.condition), rename(formula.consequence))
        return formula

    return type(constraint)(*(rename(f) for f in constraint_formulas(constraint)))  # type: ignore[arg-type]


# --- formulas with constant folding ----------------------------------------------------------


def _equal(left: str, right: str) -> Formula:
    if left == right:
        return TRUE
    if not left.startswith("?") and not right.startswith("?"):
        return FALSE  # two different objects
    return Equals(left, right)


def _and(*parts: Formula) -> Formula:
    flat: list[Formula] = []
    for part in parts:
        if part == FALSE:
            return FALSE
        flat.extend(part.args if isinstance(part, And) else (part,))
    return flat[0] if len(flat) == 1 else And(tuple(dict.fromkeys(flat)))


def _or(*parts: Formula) -> Formula:
    flat: list[Formula] = []
    for part in parts:
        if part == TRUE:
            return TRUE
        flat.extend(part.args if isinstance(part, Or) else (part,))
    return flat[0] if len(flat) == 1 else Or(tuple(dict.fromkeys(flat)))


def _not(formula: Formula) -> Formula:
    if formula == TRUE:
        return FALSE
    if formula == FALSE:
        return TRUE
    return formula.arg if isinstance(formula, Not) else Not(formula)
