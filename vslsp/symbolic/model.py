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

Writing and reading PDDL goes through unified-planning (``vslsp.symbolic.pddl``).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Iterable

from vslsp.errors import InputError
from vslsp.symbolic.formula import (
    And,
    Atom,
    Constraint,
    Formula,
    Not,
    Universe,
    atoms_of,
    formula_from_list,
    formula_to_list,
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
class Action:
    """A lifted action schema: typed parameters, a precondition and literal effects.

    ``effects`` are atoms (made true) and ``Not(atom)`` (made false), over the parameters.
    """

    name: str
    parameters: tuple[tuple[str, str], ...]
    precondition: Formula = And(())
    effects: tuple[Formula, ...] = ()

    def to_dict(self) -> dict:
        return {
            "name": self.name,
            "parameters": [list(p) for p in self.parameters],
            "precondition": formula_to_list(self.precondition),
            "effects": [formula_to_list(e) for e in self.effects],
        }

    @classmethod
    def from_dict(cls, data: dict) -> "Action":
        return cls(
            name=data["name"],
            parameters=tuple((n, t) for n, t in data["parameters"]),
            precondition=formula_from_list(data["precondition"]),  # type: ignore[arg-type]
            effects=tuple(formula_from_list(e) for e in data["effects"]),  # type: ignore[misc]
        )


@dataclass(frozen=True)
class Domain:
    """Types (``{name: parent or None}`` as pairs), predicates and action schemas."""

    name: str
    types: tuple[tuple[str, str | None], ...] = ()
    predicates: tuple[Predicate, ...] = ()
    actions: tuple[Action, ...] = ()

    # --- authoring ---
    def with_type(self, name: str, parent: str | None = None) -> "Domain":
        return replace(self, types=_put(self.types, (name, parent), key=lambda t: t[0]))

    def with_predicate(self, predicate: Predicate) -> "Domain":
        self._check_types(p for _, p in predicate.parameters)
        return replace(self, predicates=_put(self.predicates, predicate, key=lambda p: p.name))

    def with_action(self, action: Action) -> "Domain":
        self._check_types(t for _, t in action.parameters)
        known = {p.name: len(p.parameters) for p in self.predicates}
        for atom in (*atoms_of(action.precondition), *(a for e in action.effects for a in atoms_of(e))):
            if known.get(atom.predicate) != len(atom.args):
                raise InputError(f"action {action.name}: {atom.to_pddl()} does not match a declared predicate "
                                 f"({', '.join(sorted(known)) or 'none declared'}); add it with with_predicate")
        return replace(self, actions=_put(self.actions, action, key=lambda a: a.name))

    def without_action(self, name: str) -> "Domain":
        return replace(self, actions=tuple(a for a in self.actions if a.name != name))

    # --- queries ---
    def action(self, name: str) -> Action:
        for action in self.actions:
            if action.name == name:
                return action
        raise InputError(f"unknown action {name!r}; the domain {self.name} has: "
                         f"{', '.join(a.name for a in self.actions)}")

    def predicate(self, name: str) -> Predicate:
        for predicate in self.predicates:
            if predicate.name == name:
                return predicate
        raise InputError(f"unknown predicate {name!r}; the domain {self.name} has: "
                         f"{', '.join(p.name for p in self.predicates)}")

    def subtypes(self, type_: str) -> set[str]:
        """``type_`` and every type below it."""
        found = {type_}
        while True:
            more = {name for name, parent in self.types if parent in found} - found
            if not more:
                return found
            found |= more

    def to_pddl(self) -> str:
        """The domain file (written by unified-planning's PDDLWriter)."""
        from vslsp.symbolic.pddl import write_domain

        return write_domain(self)

    def to_dict(self) -> dict:
        return {
            "name": self.name,
            "types": [list(t) for t in self.types],
            "predicates": [{"name": p.name, "parameters": [list(q) for q in p.parameters]} for p in self.predicates],
            "actions": [a.to_dict() for a in self.actions],
        }

    @classmethod
    def from_dict(cls, data: dict) -> "Domain":
        return cls(
            name=data["name"],
            types=tuple((n, p) for n, p in data["types"]),
            predicates=tuple(Predicate(p["name"], tuple((n, t) for n, t in p["parameters"])) for p in data["predicates"]),
            actions=tuple(Action.from_dict(a) for a in data["actions"]),
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
    def with_objects(self, type_: str, *names: str) -> "Problem":
        self.domain._check_types([type_])
        objects = self.objects
        for name in names:
            objects = _put(objects, (name, type_), key=lambda o: o[0])
        return replace(self, objects=objects)

    def with_init(self, *atoms: Atom) -> "Problem":
        return replace(self, init=self.init | frozenset(self._checked(a) for a in atoms))

    def without_init(self, *atoms: Atom) -> "Problem":
        return replace(self, init=self.init - frozenset(atoms))

    def with_goal(self, goal: Formula) -> "Problem":
        self._checked(goal)
        return replace(self, goal=goal)

    def with_constraint(self, constraint: Constraint) -> "Problem":
        self._checked(constraint)
        return replace(self, constraints=(*self.constraints, constraint))

    def without_constraints(self) -> "Problem":
        """The same problem with no trajectory constraints: the planner chooses the order."""
        return replace(self, constraints=())

    # --- queries ---
    def universe(self) -> Universe:
        """The objects of each type, subtypes included."""
        types = {name for name, _ in self.domain.types} | {"object"}
        return {t: tuple(o for o, ot in self.objects if ot in self.domain.subtypes(t) or t == "object")
                for t in types}

    def to_pddl(self) -> str:
        """The problem file with ``:constraints`` (written by unified-planning's PDDLWriter)."""
        from vslsp.symbolic.pddl import write_problem

        return write_problem(self)

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
    def from_dict(cls, data: dict) -> "Problem":
        return cls(
            name=data["name"],
            domain=Domain.from_dict(data["domain"]),
            objects=tuple((n, t) for n, t in data["objects"]),
            init=frozenset(formula_from_list(a) for a in data["init"]),
            goal=formula_from_list(data["goal"]),  # type: ignore[arg-type]
            constraints=tuple(formula_from_list(c) for c in data["constraints"]),  # type: ignore[misc]
        )

    def _checked(self, formula):
        """Raise InputError when ``formula`` names an undeclared predicate or object."""
        arity = {p.name: len(p.parameters) for p in self.domain.predicates}
        objects = {o for o, _ in self.objects}
        for atom in atoms_of(formula):
            if arity.get(atom.predicate) != len(atom.args):
                raise InputError(f"{atom.to_pddl()} does not match a predicate of domain {self.domain.name} "
                                 f"({', '.join(sorted(arity))})")
            for arg in atom.args:
                if not arg.startswith("?") and arg not in objects:
                    raise InputError(f"{atom.to_pddl()} names {arg!r}, which is not an object of problem "
                                     f"{self.name}; add it with with_objects")
        return formula


def _put(items: tuple, item, key) -> tuple:
    """``items`` with ``item`` replacing the one with the same key, or appended."""
    keys = [key(i) for i in items]
    if key(item) in keys:
        index = keys.index(key(item))
        return (*items[:index], item, *items[index + 1:])
    return (*items, item)


def ground_effects(action: Action, args: tuple[str, ...]) -> tuple[frozenset, frozenset]:
    """(atoms added, atoms deleted) by ``action`` applied to objects ``args``."""
    from vslsp.symbolic.formula import substitute

    binding = dict(zip((p for p, _ in action.parameters), args))
    added, deleted = set(), set()
    for effect in action.effects:
        ground = substitute(effect, binding)
        (deleted.add(ground.arg) if isinstance(ground, Not) else added.add(ground))
    return frozenset(added), frozenset(deleted)
