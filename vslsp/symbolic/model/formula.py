"""Logical formulas and PDDL 3.0 trajectory constraints: the symbolic vocabulary of VSL-SP.

Paper: "Generalization of Learned Skills as Symbolic Action Models" and "Implementation":
one predicate, ``(far ?b)``, describes push and pull; goals such as "no block is far" and the
demonstrated order, which PDDL 3.0 writes as trajectory constraints. The operator the paper
calls "somewhere-after" is PDDL 3.0's ``(sometime-before p q)``: p may only hold after q has
held.

Formulas are small frozen values. Terms are strings: ``"?b"`` is a variable, anything else an
object. A state is a ``frozenset`` of ground :class:`Atom`. Every formula prints as PDDL
(``to_pddl``) and as nested JSON lists (``to_list`` / :func:`formula_from_list`).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from typing import ClassVar

from vslsp.errors import InputError
from vslsp.symbolic.budget import check_instances, instance_count

State = frozenset  # frozenset[Atom]: the atoms that hold
#: Objects of each type, subtypes included: ``{"block": ("red", "green")}``.
Universe = Mapping[str, tuple[str, ...]]


class _Connectives:
    """``~f``, ``f & g`` and ``f | g`` build formulas, for authoring in a notebook."""

    def __invert__(self) -> Not:
        return Not(self)  # type: ignore[arg-type]

    def __and__(self, other: Formula) -> And:
        return And((self, other))  # type: ignore[arg-type]

    def __or__(self, other: Formula) -> Or:
        return Or((self, other))  # type: ignore[arg-type]


@dataclass(frozen=True)
class Atom(_Connectives):
    """``(predicate arg ...)``; ``args`` are variables (``"?b"``) or object names."""

    predicate: str
    args: tuple[str, ...] = ()

    def to_pddl(self) -> str:
        return "(" + " ".join((self.predicate, *self.args)) + ")"


@dataclass(frozen=True)
class Not(_Connectives):
    arg: Formula

    def to_pddl(self) -> str:
        return f"(not {self.arg.to_pddl()})"


@dataclass(frozen=True)
class And(_Connectives):
    args: tuple[Formula, ...]

    def to_pddl(self) -> str:
        return "(and " + " ".join(a.to_pddl() for a in self.args) + ")" if self.args else "(and)"


@dataclass(frozen=True)
class Or(_Connectives):
    args: tuple[Formula, ...]

    def to_pddl(self) -> str:
        return "(or " + " ".join(a.to_pddl() for a in self.args) + ")"


@dataclass(frozen=True)
class Imply(_Connectives):
    condition: Formula
    consequence: Formula

    def to_pddl(self) -> str:
        return f"(imply {self.condition.to_pddl()} {self.consequence.to_pddl()})"


@dataclass(frozen=True)
class Forall(_Connectives):
    """``(forall (?b - block) body)``; ``variables`` are ``(("?b", "block"), ...)``."""

    variables: tuple[tuple[str, str], ...]
    body: Formula

    def to_pddl(self) -> str:
        return f"(forall ({_typed(self.variables)}) {self.body.to_pddl()})"


@dataclass(frozen=True)
class Exists(_Connectives):
    variables: tuple[tuple[str, str], ...]
    body: Formula

    def to_pddl(self) -> str:
        return f"(exists ({_typed(self.variables)}) {self.body.to_pddl()})"


@dataclass(frozen=True)
class Equals(_Connectives):
    """``(= ?a ?b)``: two terms name the same object (PDDL's ``:equality``)."""

    left: str
    right: str

    def to_pddl(self) -> str:
        return f"(= {self.left} {self.right})"


Formula = Atom | Not | And | Or | Imply | Forall | Exists | Equals


# --- PDDL 3.0 trajectory constraints -------------------------------------------------------


class _Trajectory:
    """A PDDL 3.0 constraint; prints as ``(keyword formula ...)``."""

    keyword: ClassVar[str]

    def to_pddl(self) -> str:
        return f"({self.keyword} " + " ".join(f.to_pddl() for f in constraint_formulas(self)) + ")"  # type: ignore[arg-type]


@dataclass(frozen=True)
class _OneFormula(_Trajectory):
    formula: Formula


class Always(_OneFormula):
    """φ holds in every state of the trajectory."""

    keyword = "always"


class Sometime(_OneFormula):
    """φ holds in some state."""

    keyword = "sometime"


class AtMostOnce(_OneFormula):
    """φ holds during at most one contiguous stretch of states."""

    keyword = "at-most-once"


class AtEnd(_OneFormula):
    """φ holds in the last state (PDDL 3.0 ``(at end φ)``; written into the goal)."""

    keyword = "at end"


@dataclass(frozen=True)
class SometimeBefore(_Trajectory):
    """``(sometime-before p q)``: whenever p holds, q held in a strictly earlier state.

    This is "p only after q": the demonstrated order (the paper's "somewhere-after").
    """

    formula: Formula  # p
    before: Formula  # q
    keyword: ClassVar[str] = "sometime-before"


@dataclass(frozen=True)
class SometimeAfter(_Trajectory):
    """``(sometime-after p q)``: whenever p holds, q holds then or later."""

    formula: Formula  # p
    after: Formula  # q
    keyword: ClassVar[str] = "sometime-after"


Constraint = Always | Sometime | AtMostOnce | AtEnd | SometimeBefore | SometimeAfter
CONSTRAINT_KEYWORDS = ("always", "sometime", "at-most-once", "sometime-before", "sometime-after", "at end")


def sometime_before(later: Formula, earlier: Formula) -> SometimeBefore:
    """``later`` may only hold after ``earlier`` has held: the demonstrated order."""
    return SometimeBefore(later, earlier)


def forall(variables: tuple[str, str] | Iterable[tuple[str, str]], body: Formula) -> Forall:
    """``forall(("?b", "block"), ~far("?b"))`` or with several ``(variable, type)`` pairs."""
    variables = tuple(variables)  # type: ignore[arg-type]
    if variables and isinstance(variables[0], str):
        variables = (variables,)  # type: ignore[assignment]
    return Forall(tuple(tuple(v) for v in variables), body)  # type: ignore[misc]


def conjunction(formulas: Iterable[Formula]) -> Formula:
    """The conjunction of ``formulas``, flattened; a single formula stays itself."""
    flat: list[Formula] = []
    for formula in formulas:
        flat.extend(formula.args if isinstance(formula, And) else (formula,))
    unique = tuple(dict.fromkeys(flat))
    return unique[0] if len(unique) == 1 else And(unique)


def literal(predicate: str, args: tuple[str, ...], value: bool) -> Atom | Not:
    """``(predicate args)`` when ``value`` else ``(not (predicate args))``."""
    atom = Atom(predicate, tuple(args))
    return atom if value else Not(atom)


def _typed(variables: tuple[tuple[str, str], ...]) -> str:
    return " ".join(f"{name} - {type_}" for name, type_ in variables)


# --- substitution, evaluation --------------------------------------------------------------


def substitute(formula: Formula, binding: Mapping[str, str]) -> Formula:
    """Replace variables by objects: ``substitute(far("?b"), {"?b": "red"}) == far("red")``."""
    if isinstance(formula, Atom):
        return Atom(formula.predicate, tuple(binding.get(a, a) for a in formula.args))
    if isinstance(formula, Equals):
        return Equals(binding.get(formula.left, formula.left), binding.get(formula.right, formula.right))
    if isinstance(formula, (Forall, Exists)):
        inner = {k: v for k, v in binding.items() if k not in dict(formula.variables)}
        return type(formula)(formula.variables, substitute(formula.body, inner))
    return _map_connective(formula, lambda part: substitute(part, binding))


def _map_connective(formula: Formula, transform: Callable[[Formula], Formula]) -> Formula:
    """The connective ``formula`` (not, and, or, imply) rebuilt over its transformed parts."""
    if isinstance(formula, Not):
        return Not(transform(formula.arg))
    if isinstance(formula, (And, Or)):
        return type(formula)(tuple(transform(a) for a in formula.args))
    assert isinstance(formula, Imply), formula
    return Imply(transform(formula.condition), transform(formula.consequence))


def holds(formula: Formula, state: State, universe: Universe) -> bool:
    """Whether a ground ``formula`` holds in ``state`` (a frozenset of ground atoms).

    Quantifiers range over ``universe[type]``, the objects of each type.
    """
    if isinstance(formula, Atom):
        return formula in state
    if isinstance(formula, Equals):
        return formula.left == formula.right
    if isinstance(formula, Not):
        return not holds(formula.arg, state, universe)
    if isinstance(formula, And):
        return all(holds(a, state, universe) for a in formula.args)
    if isinstance(formula, Or):
        return any(holds(a, state, universe) for a in formula.args)
    if isinstance(formula, Imply):
        return not holds(formula.condition, state, universe) or holds(formula.consequence, state, universe)
    test: Callable = all if isinstance(formula, Forall) else any
    return test(
        holds(substitute(formula.body, binding), state, universe) for binding in bindings(formula.variables, universe)
    )


def expand_quantifiers(formula: Formula, universe: Universe, what: str = "the formula") -> Formula:
    """``formula`` with ``forall`` as a conjunction and ``exists`` as a disjunction over the objects.

    Planners get a plain goal this way: Fast Downward turns a quantified goal into one derived
    atom, which leaves its heuristics blind on long plans. The atoms it would write are counted
    first (:func:`ground_size`): more than :data:`~vslsp.symbolic.budget.MAX_GROUND_INSTANCES` is an
    InputError naming ``what`` (the goal, a constraint), before anything is built.
    """
    check_instances(ground_size(formula, universe), what)
    return _expanded(formula, universe)


def _expanded(formula: Formula, universe: Universe) -> Formula:
    if isinstance(formula, (Atom, Equals)):
        return formula
    if isinstance(formula, (Forall, Exists)):
        parts = tuple(_expanded(substitute(formula.body, b), universe) for b in bindings(formula.variables, universe))
        return And(parts) if isinstance(formula, Forall) else Or(parts)
    return _map_connective(formula, lambda part: _expanded(part, universe))


def ground_size(formula: Formula, universe: Universe) -> int:
    """How many atoms ``formula`` has once its quantifiers are written out over ``universe`` (counted
    without writing them: a quantifier multiplies its body's count by its bindings)."""
    if isinstance(formula, (Atom, Equals)):
        return 1
    if isinstance(formula, Not):
        return ground_size(formula.arg, universe)
    if isinstance(formula, (And, Or)):
        return sum(ground_size(arg, universe) for arg in formula.args)
    if isinstance(formula, Imply):
        return ground_size(formula.condition, universe) + ground_size(formula.consequence, universe)
    return instance_count(formula.variables, universe) * ground_size(formula.body, universe)


def bindings(variables: tuple[tuple[str, str], ...], universe: Universe) -> Iterable[dict[str, str]]:
    if not variables:
        yield {}
        return
    (name, type_), rest = variables[0], variables[1:]
    for obj in universe.get(type_, ()):
        for binding in bindings(rest, universe):
            yield {name: obj, **binding}


def atoms_of(formula: Formula | Constraint) -> Iterable[Atom]:
    """Every atom written in a formula or constraint (variables left as they are)."""
    if isinstance(formula, Atom):
        yield formula
    elif isinstance(formula, Equals):
        return
    elif isinstance(formula, Not):
        yield from atoms_of(formula.arg)
    elif isinstance(formula, (And, Or)):
        for arg in formula.args:
            yield from atoms_of(arg)
    elif isinstance(formula, Imply):
        yield from atoms_of(formula.condition)
        yield from atoms_of(formula.consequence)
    elif isinstance(formula, (Forall, Exists)):
        yield from atoms_of(formula.body)
    else:
        for part in constraint_formulas(formula):
            yield from atoms_of(part)


def constraint_formulas(constraint: Constraint) -> tuple[Formula, ...]:
    """The formulas a constraint speaks of: (φ,) or (p, q)."""
    if isinstance(constraint, SometimeBefore):
        return constraint.formula, constraint.before
    if isinstance(constraint, SometimeAfter):
        return constraint.formula, constraint.after
    return (constraint.formula,)


# --- JSON: nested lists, the s-expression spelled in JSON ----------------------------------


def formula_to_list(formula: Formula | Constraint) -> list:
    """``(forall (?b - block) (not (far ?b)))`` -> ``["forall", [["?b", "block"]], ["not", ["far", "?b"]]]``."""
    if isinstance(formula, Atom):
        return [formula.predicate, *formula.args]
    if isinstance(formula, Equals):
        return ["=", formula.left, formula.right]
    if isinstance(formula, Not):
        return ["not", formula_to_list(formula.arg)]
    if isinstance(formula, (And, Or)):
        return [type(formula).__name__.lower(), *(formula_to_list(a) for a in formula.args)]
    if isinstance(formula, Imply):
        return ["imply", formula_to_list(formula.condition), formula_to_list(formula.consequence)]
    if isinstance(formula, (Forall, Exists)):
        return [type(formula).__name__.lower(), [list(v) for v in formula.variables], formula_to_list(formula.body)]
    return [formula.keyword, *(formula_to_list(f) for f in constraint_formulas(formula))]


_CONSTRAINTS = {c.keyword: c for c in (Always, Sometime, AtMostOnce, AtEnd, SometimeBefore, SometimeAfter)}


def formula_from_list(data: list) -> Formula | Constraint:
    """Inverse of :func:`formula_to_list`."""
    if not isinstance(data, list) or not data or not isinstance(data[0], str):
        raise InputError(f"not a formula: {data!r} (expected a list like ['far', '?b'])")
    head, rest = data[0], data[1:]
    if head == "not":
        return Not(formula_from_list(rest[0]))  # type: ignore[arg-type]
    if head in ("and", "or"):
        return (And if head == "and" else Or)(tuple(formula_from_list(a) for a in rest))  # type: ignore[misc]
    if head == "imply":
        return Imply(formula_from_list(rest[0]), formula_from_list(rest[1]))  # type: ignore[arg-type]
    if head in ("forall", "exists"):
        variables = tuple((str(n), str(t)) for n, t in rest[0])
        return (Forall if head == "forall" else Exists)(variables, formula_from_list(rest[1]))  # type: ignore[arg-type]
    if head == "=" and len(rest) == 2 and all(isinstance(a, str) for a in rest):
        return Equals(rest[0], rest[1])
    if head in _CONSTRAINTS:
        return _CONSTRAINTS[head](*(formula_from_list(a) for a in rest))  # type: ignore[arg-type]
    if not all(isinstance(a, str) for a in rest):
        raise InputError(f"not a formula: {data!r} (atom arguments must be names)")
    return Atom(head, tuple(rest))
