"""A flat problem read straight from the language engine's tree, without unified-planning's reader.

Paper: "Implementation" (the problem file VSL-SP writes: objects, the initial state, a goal). A
problem whose goal is a ground literal or a conjunction of them, with no constraints and no metric,
is what a scene or a large generated task gives: tens of thousands of objects and atoms. unified-
planning's reader parses it through a grammar at about a millisecond per atom and looks each object
up in a list (time quadratic in the objects: 20 000 objects and a goal of 20 000 atoms take over a
minute). The language engine (:mod:`vslsp.symbolic.language`) reads and checks the same files in
linear time, so :func:`flat_problem` builds our :class:`~vslsp.symbolic.model.domain.Problem` from its tree
when the files check clean and the problem is flat; any other problem (``None``) goes to the reader,
which then also words the errors. Both give the same Problem (tests/symbolic/test_flat_problem.py).
"""

from __future__ import annotations

from vslsp.symbolic.language import analyse
from vslsp.symbolic.language.syntax import Group, Token
from vslsp.symbolic.model.domain import Domain, Problem
from vslsp.symbolic.model.formula import And, Atom, Formula, Not, conjunction

#: The sections a flat problem may have.
_FLAT_SECTIONS = frozenset((":domain", ":requirements", ":objects", ":init", ":goal"))


def flat_problem(domain: Domain, domain_text: str, problem_text: str) -> Problem | None:
    """The problem of ``problem_text`` (for ``domain``, read from ``domain_text``) when it checks clean
    and is flat (ground literals in the goal, atoms in the initial state, no constraints or metric);
    else None."""
    analysis = analyse(domain_text, "<domain>", problem_text, "<problem>")
    if analysis.errors or analysis.problem_name is None:
        return None
    sections = analysis.sections("<problem>")
    define = analysis.documents["<problem>"].groups[0]
    keys = [item.key for item in define.items[2:] if isinstance(item, Group)]
    if not set(keys) <= _FLAT_SECTIONS or len(keys) != len(set(keys)) or ":goal" not in sections:
        return None
    objects = _objects(sections.get(":objects"), domain)
    init = _atoms(sections[":init"].items[1:] if ":init" in sections else [])
    goal_items = sections[":goal"].items[1:]
    goal = _goal(goal_items[0]) if len(goal_items) == 1 else None
    if objects is None or init is None or goal is None:
        return None
    return Problem(analysis.problem_name.lower(), domain, objects, frozenset(init), goal)


def _objects(section: Group | None, domain: Domain) -> tuple[tuple[str, str], ...] | None:
    """``((name, type), ...)`` of ``(:objects a b - t c)``, or None for anything but names of one type
    each, declared once, that name nothing else of the domain."""
    if section is None:
        return ()
    # unified-planning's reader refuses a name given to two things (an object and a predicate ...): such a
    # problem goes to it, for its message
    taken = {name for name, _ in domain.constants} | {name for name, _ in domain.types} | {"object"}
    taken |= {p.name for p in domain.predicates} | {a.name for a in domain.actions}
    found: list[tuple[str, str]] = []
    pending: list[str] = []
    items = section.items[1:]
    index = 0
    while index < len(items):
        item = items[index]
        if not isinstance(item, Token):
            return None
        if item.text == "-":
            kind = items[index + 1] if index + 1 < len(items) else None
            if not isinstance(kind, Token):
                return None
            found.extend((name, kind.key) for name in pending)
            pending = []
            index += 2
            continue
        pending.append(item.key)
        index += 1
    found.extend((name, "object") for name in pending)
    if any(name in taken for name, _ in found) or len({name for name, _ in found}) != len(found):
        return None
    return tuple(found)


def _atom(node: Token | Group) -> Atom | None:
    """``(predicate name ...)`` with names only, or None."""
    if not isinstance(node, Group) or node.head is None or node.key in ("and", "not", "="):
        return None
    args = node.items[1:]
    if not all(isinstance(arg, Token) and not arg.key.startswith("?") for arg in args):
        return None
    return Atom(node.key, tuple(arg.key for arg in args))  # type: ignore[union-attr]


def _atoms(items: list[Token | Group]) -> list[Atom] | None:
    atoms = [_atom(item) for item in items]
    return None if any(atom is None for atom in atoms) else atoms  # type: ignore[return-value]


def _literal(node: Token | Group) -> Formula | None:
    if isinstance(node, Group) and node.key == "not":
        inner = _atom(node.items[1]) if len(node.items) == 2 else None
        return Not(inner) if inner is not None else None
    return _atom(node)


def _goal(node: Token | Group) -> Formula | None:
    """A ground literal, or ``(and literal ...)`` as the reader's conjunction; None for anything else."""
    if isinstance(node, Group) and node.key == "and":
        parts = [_literal(item) for item in node.items[1:]]
        if any(part is None for part in parts):
            return None
        return conjunction(parts) if parts else And(())  # type: ignore[arg-type]
    return _literal(node)
