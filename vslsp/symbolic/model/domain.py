"""PDDL domains and problems as frozen values, built by learning or by hand.

Paper: "Generalization of Learned Skills as Symbolic Action Models" (Table 3: push and pull
with ``(far ?b)``) and "Implementation" (the problem with its goal and trajectory
constraints). Learned models and hand-written ones are the same objects; every ``with_*``
method returns an edited copy, so a notebook can build a domain step by step::

    far = Predicate("far", (("?b", "block"),))
    domain = (Domain("vsl-sp").with_type("block").with_predicate(far)
              .with_action(Action("push", (("?b", "block"),), ~far("?b"), (far("?b"),))))
    problem = (Problem("p", domain).with_objects("block", "red", "green")
               .with_init(far("red")).with_goal(forall(("?b", "block"), ~far("?b"))))
    print(problem.to_pddl())

A model prints itself as PDDL (``to_pddl``, as every formula does); reading files is
:mod:`vslsp.symbolic.io.pddl`, which imports this module and never the other way round.
Actions have literal effects and conditional ones (:class:`When`, optionally universal),
preconditions may use equality (:class:`~vslsp.symbolic.model.formula.Equals`) and domain constants.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field, replace

from vslsp.errors import InputError
from vslsp.symbolic.model.formula import (
    And,
    Atom,
    Constraint,
    Formula,
    Not,
    Universe,
    atoms_of,
    bindings,
    formula_from_list,
    formula_to_list,
    holds,
    substitute,
)


@dataclass(frozen=True)
class Predicate:
    """``(far ?b - block)``: a name and typed parameters ``(("?b", "block"),)``."""

    name: str
    parameters: tuple[tuple[str, str], ...] = ()

    def __call__(self, *args: str) -> Atom:
        if len(args) != len(self.parameters):
            raise InputError(f"{self.name} takes {len(self.parameters)} arguments, got {len(args)}: {args}")
        return Atom(self.name, tuple(args))


@dataclass(frozen=True)
class When:
    """A conditional effect ``(when condition (and literal ...))``, universal over ``variables`` if any:
    ``(forall (?x - t) (when condition ...))``. The condition is read in the state before the action."""

    condition: Formula
    effects: tuple[Formula, ...]  # Atom or Not(Atom)
    variables: tuple[tuple[str, str], ...] = ()

    def to_pddl(self, timed: bool = False) -> str:
        """``timed``: as in a durative action, the condition ``(at start ...)``, each literal ``(at end ...)``."""
        start, end = ("(at start ", "(at end ") if timed else ("", "")
        close = ")" if timed else ""
        literals = " ".join(f"{end}{e.to_pddl()}{close}" for e in self.effects)
        body = literals if len(self.effects) == 1 else f"(and {literals})"
        if self.condition != And(()):
            body = f"(when {start}{self.condition.to_pddl()}{close} {body})"
        if self.variables:
            body = f"(forall ({_typed(self.variables)}) {body})"
        return body

    def to_list(self) -> list:
        return [
            "when",
            [list(v) for v in self.variables],
            formula_to_list(self.condition),
            [formula_to_list(e) for e in self.effects],
        ]


Effect = Atom | Not | When


def _effect_from_list(data: list) -> Effect:
    if data and data[0] == "when":
        return When(
            formula_from_list(data[2]),  # type: ignore[arg-type]
            tuple(formula_from_list(e) for e in data[3]),  # type: ignore[arg-type, misc]
            tuple((str(n), str(t)) for n, t in data[1]),
        )
    return formula_from_list(data)  # type: ignore[return-value]


@dataclass(frozen=True)
class Action:
    """A lifted action schema: typed parameters, a precondition and effects.

    ``effects`` are atoms (made true), ``Not(atom)`` (made false) and :class:`When` (conditional).
    """

    name: str
    parameters: tuple[tuple[str, str], ...]
    precondition: Formula = And(())
    effects: tuple[Effect, ...] = ()

    def to_pddl(self) -> str:
        lines = [f"  (:action {self.name}", f"    :parameters ({_typed(self.parameters)})"]
        if self.precondition != And(()):
            lines.append(f"    :precondition {self.precondition.to_pddl()}")
        lines.append(f"    :effect (and {' '.join(e.to_pddl() for e in self.effects)})".replace("(and )", "(and)"))
        return "\n".join(lines) + ")"

    def to_dict(self) -> dict:
        return {
            "name": self.name,
            "parameters": [list(p) for p in self.parameters],
            "precondition": formula_to_list(self.precondition),
            "effects": [e.to_list() if isinstance(e, When) else formula_to_list(e) for e in self.effects],
        }

    @classmethod
    def from_dict(cls, data: dict) -> Action:
        return cls(
            name=data["name"],
            parameters=tuple((n, t) for n, t in data["parameters"]),
            precondition=formula_from_list(data["precondition"]),  # type: ignore[arg-type]
            effects=tuple(_effect_from_list(e) for e in data["effects"]),
        )

    def effect_atoms(self) -> Iterable[Atom]:
        """The atoms the effects write (lifted)."""
        for effect in self.effects:
            for literal_ in effect.effects if isinstance(effect, When) else (effect,):
                yield literal_.arg if isinstance(literal_, Not) else literal_  # type: ignore[misc]


@dataclass(frozen=True)
class Domain:
    """Types (``{name: parent or None}`` as pairs), predicates, action schemas and constants
    (objects every problem of the domain has, ``((name, type), ...)``)."""

    name: str
    types: tuple[tuple[str, str | None], ...] = ()
    predicates: tuple[Predicate, ...] = ()
    actions: tuple[Action, ...] = ()
    constants: tuple[tuple[str, str], ...] = ()

    # --- authoring ---
    def with_type(self, name: str, parent: str | None = None) -> Domain:
        return self.with_types(parent, name)

    def with_types(self, parent: str | None, *names: str) -> Domain:
        """The domain with the types ``names`` under ``parent`` (a type declared again keeps its place)."""
        types = dict(self.types)
        types.update(dict.fromkeys(names, parent))
        return replace(self, types=tuple(types.items()))

    def with_predicate(self, predicate: Predicate) -> Domain:
        self._check_types(p for _, p in predicate.parameters)
        return replace(self, predicates=_put(self.predicates, predicate, key=lambda p: p.name))

    def with_constant(self, name: str, type_: str) -> Domain:
        self._check_types([type_])
        return replace(self, constants=_put(self.constants, (name, type_), key=lambda c: c[0]))

    def with_action(self, action: Action) -> Domain:
        self._check_types(t for _, t in action.parameters)
        known = {p.name: len(p.parameters) for p in self.predicates}
        conditions = [action.precondition, *(e.condition for e in action.effects if isinstance(e, When))]
        for atom in (*(a for c in conditions for a in atoms_of(c)), *action.effect_atoms()):
            if known.get(atom.predicate) != len(atom.args):
                raise InputError(
                    f"action {action.name}: {atom.to_pddl()} does not match a declared predicate "
                    f"({', '.join(sorted(known)) or 'none declared'}); add it with with_predicate"
                )
        return replace(self, actions=_put(self.actions, action, key=lambda a: a.name))

    def without_action(self, name: str) -> Domain:
        return replace(self, actions=tuple(a for a in self.actions if a.name != name))

    # --- queries ---
    def action(self, name: str) -> Action:
        for action in self.actions:
            if action.name == name:
                return action
        raise InputError(
            f"unknown action {name!r}; the domain {self.name} has: {', '.join(a.name for a in self.actions)}"
        )

    def predicate(self, name: str) -> Predicate:
        for predicate in self.predicates:
            if predicate.name == name:
                return predicate
        raise InputError(
            f"unknown predicate {name!r}; the domain {self.name} has: {', '.join(p.name for p in self.predicates)}"
        )

    def subtypes(self, type_: str) -> set[str]:
        """``type_`` and every type below it (time linear in the types, whatever the depth)."""
        children: dict[str | None, list[str]] = {}
        for name, parent in self.types:
            children.setdefault(parent, []).append(name)
        found = {type_}
        pending = [type_]
        while pending:
            for child in children.get(pending.pop(), ()):
                if child not in found:
                    found.add(child)
                    pending.append(child)
        return found

    def requirements(self) -> tuple[str, ...]:
        """The PDDL requirements the domain needs (``:constraints`` always: problems may order it)."""
        needed = [":strips", ":typing"]
        conditions = [a.precondition for a in self.actions] + [
            e.condition for a in self.actions for e in a.effects if isinstance(e, When)
        ]
        text = " ".join(c.to_pddl() for c in conditions)
        for word, requirement in (
            ("(not ", ":negative-preconditions"),
            ("(or ", ":disjunctive-preconditions"),
            ("(imply ", ":disjunctive-preconditions"),
            ("(= ", ":equality"),
            ("(exists ", ":existential-preconditions"),
            ("(forall ", ":universal-preconditions"),
        ):
            if word in text and requirement not in needed:
                needed.append(requirement)
        if any(isinstance(e, When) for a in self.actions for e in a.effects):
            needed.append(":conditional-effects")
        return (*needed, ":constraints")

    def to_pddl(self) -> str:
        """The domain file."""
        roots = [name for name, parent in self.types if not parent]
        types = " ".join(
            [
                *([" ".join(roots) + " - object"] if roots else []),
                *(f"{name} - {parent}" for name, parent in self.types if parent),
            ]
        )
        lines = [f"(define (domain {self.name})", f"  (:requirements {' '.join(self.requirements())})"]
        if self.types:
            lines.append(f"  (:types {types})")
        if self.constants:
            lines.append(f"  (:constants {_typed(self.constants, bare=True)})")
        if self.predicates:  # PDDL has no empty (:predicates)
            lines.append("  (:predicates")
            lines.extend(f"    ({p.name}{' ' if p.parameters else ''}{_typed(p.parameters)})" for p in self.predicates)
            lines[-1] += ")"
        return "\n".join(lines) + "\n" + "".join(f"\n{a.to_pddl()}\n" for a in self.actions) + ")\n"

    def to_dict(self) -> dict:
        return {
            "name": self.name,
            "types": [list(t) for t in self.types],
            "predicates": [{"name": p.name, "parameters": [list(q) for q in p.parameters]} for p in self.predicates],
            "actions": [a.to_dict() for a in self.actions],
            "constants": [list(c) for c in self.constants],
        }

    @classmethod
    def from_dict(cls, data: dict) -> Domain:
        return cls(
            name=data["name"],
            types=tuple((n, p) for n, p in data["types"]),
            predicates=tuple(
                Predicate(p["name"], tuple((n, t) for n, t in p["parameters"])) for p in data["predicates"]
            ),
            actions=tuple(Action.from_dict(a) for a in data["actions"]),
            constants=tuple((n, t) for n, t in data.get("constants", ())),
        )

    def _check_types(self, types: Iterable[str]) -> None:
        declared = {name for name, _ in self.types} | {"object"}
        for type_ in types:
            if type_ not in declared:
                raise InputError(f"undefined type {type_!r} in domain {self.name}; add it with with_type")


@dataclass(frozen=True)
class Problem:
    """Objects ``((name, type), ...)``, the initial state, the goal and trajectory constraints."""

    name: str
    domain: Domain
    objects: tuple[tuple[str, str], ...] = ()
    init: frozenset = field(default_factory=frozenset)  # frozenset[Atom], ground
    goal: Formula = And(())
    constraints: tuple[Constraint, ...] = ()

    # --- authoring ---
    def with_objects(self, type_: str, *names: str) -> Problem:
        self.domain._check_types([type_])
        objects = dict(self.objects)  # an object named again keeps its place and takes the new type
        objects.update(dict.fromkeys(names, type_))
        return replace(self, objects=tuple(objects.items()))

    def with_init(self, *atoms: Atom) -> Problem:
        self._checked(*atoms)
        return replace(self, init=self.init | frozenset(atoms))

    def without_init(self, *atoms: Atom) -> Problem:
        return replace(self, init=self.init - frozenset(atoms))

    def with_goal(self, goal: Formula) -> Problem:
        self._checked(goal)
        return replace(self, goal=goal)

    def with_constraint(self, constraint: Constraint) -> Problem:
        self._checked(constraint)
        return replace(self, constraints=(*self.constraints, constraint))

    def without_constraints(self) -> Problem:
        """The same problem with no trajectory constraints: the planner chooses the order."""
        return replace(self, constraints=())

    # --- queries ---
    def all_objects(self) -> tuple[tuple[str, str], ...]:
        """The domain's constants and the problem's objects, ``((name, type), ...)``."""
        constants = set(self.domain.constants)
        return (*self.domain.constants, *(o for o in self.objects if o not in constants))

    def universe(self) -> Universe:
        """The objects of each type (constants and subtypes included)."""
        types = {name for name, _ in self.domain.types} | {"object"}
        below = {t: self.domain.subtypes(t) for t in types}
        everything = self.all_objects()
        return {t: tuple(o for o, ot in everything if t == "object" or ot in below[t]) for t in types}

    def to_pddl(self) -> str:
        """The problem file, each goal part and each trajectory constraint on a line of its own."""
        lines = [f"(define (problem {self.name})", f"  (:domain {self.domain.name})"]
        if self.objects:
            lines.append(f"  (:objects {_typed(self.objects, bare=True)})")
        lines.append("  (:init")
        lines.extend(f"    {a.to_pddl()}" for a in sorted(self.init, key=lambda a: (a.predicate, a.args)))
        lines[-1] += ")"
        lines.extend(_section(":goal", [self.goal]))
        if self.constraints:
            lines.extend(_section(":constraints", [c.to_pddl() for c in self.constraints]))
        return "\n".join(lines) + ")\n"

    def to_dict(self) -> dict:
        return {
            "name": self.name,
            "domain": self.domain.to_dict(),
            "objects": [list(o) for o in self.objects],
            "init": sorted(formula_to_list(a) for a in self.init),
            "goal": formula_to_list(self.goal),
            "constraints": [formula_to_list(c) for c in self.constraints],
        }

    @classmethod
    def from_dict(cls, data: dict) -> Problem:
        return cls(
            name=data["name"],
            domain=Domain.from_dict(data["domain"]),
            objects=tuple((n, t) for n, t in data["objects"]),
            init=frozenset(formula_from_list(a) for a in data["init"]),
            goal=formula_from_list(data["goal"]),  # type: ignore[arg-type]
            constraints=tuple(formula_from_list(c) for c in data["constraints"]),  # type: ignore[misc]
        )

    def _checked(self, *formulas):
        """Raise InputError when one of ``formulas`` names an undeclared predicate or object (the names
        gathered once for all of them)."""
        arity = {p.name: len(p.parameters) for p in self.domain.predicates}
        objects = {o for o, _ in self.all_objects()}
        for atom in (atom for formula in formulas for atom in atoms_of(formula)):
            if arity.get(atom.predicate) != len(atom.args):
                raise InputError(
                    f"{atom.to_pddl()} does not match a predicate of domain {self.domain.name} "
                    f"({', '.join(sorted(arity))})"
                )
            for arg in atom.args:
                if not arg.startswith("?") and arg not in objects:
                    raise InputError(
                        f"{atom.to_pddl()} names {arg!r}, which is not an object of problem "
                        f"{self.name}; add it with with_objects"
                    )


def _put(items: tuple, item, key) -> tuple:
    """``items`` with ``item`` replacing the one with the same key, or appended."""
    keys = [key(i) for i in items]
    if key(item) in keys:
        index = keys.index(key(item))
        return (*items[:index], item, *items[index + 1 :])
    return (*items, item)


def _typed(parameters: tuple[tuple[str, str], ...], bare: bool = False) -> str:
    """``?b - block ?c - block`` (``bare``: names without ``?`` such as objects, grouped by type)."""
    if not bare:
        return " ".join(f"{name} - {type_}" for name, type_ in parameters)
    groups: dict[str, list[str]] = {}
    for name, type_ in parameters:
        groups.setdefault(type_, []).append(name)
    return " ".join(f"{' '.join(names)} - {type_}" for type_, names in groups.items())


def _section(keyword: str, items: list) -> list[str]:
    """``(:goal (and A B))`` laid out with A and B on lines of their own."""
    parts = [p for item in items for p in (item.args if isinstance(item, And) else (item,))]
    texts = [p if isinstance(p, str) else p.to_pddl() for p in parts]
    if len(texts) == 1:
        return [f"  ({keyword} {texts[0]})"]
    return [f"  ({keyword} (and", *(f"    {t}" for t in texts), "  ))"]


def ground_effects(
    action: Action, args: tuple[str, ...], state: frozenset = frozenset(), universe: Universe | None = None
) -> tuple[frozenset, frozenset]:
    """(atoms added, atoms deleted) by ``action`` applied to objects ``args`` in ``state``.

    Conditional effects are read in ``state``; universal ones range over ``universe``.
    """
    binding = dict(zip((p for p, _ in action.parameters), args, strict=False))
    added, deleted = set(), set()
    for effect in action.effects:
        if not isinstance(effect, When):
            ground = substitute(effect, binding)
            (deleted.add(ground.arg) if isinstance(ground, Not) else added.add(ground))
            continue
        for extra in bindings(effect.variables, universe or {}):
            local = {**binding, **extra}
            if holds(substitute(effect.condition, local), state, universe or {}):
                for literal_ in effect.effects:
                    ground = substitute(literal_, local)
                    (deleted.add(ground.arg) if isinstance(ground, Not) else added.add(ground))
    return frozenset(added), frozenset(deleted - added)
