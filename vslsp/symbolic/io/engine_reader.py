"""Reading a domain and a problem from the language engine's tree, without unified-planning.

Paper: "Implementation" (PDDL 3.0 domains and problems, planned by Fast Downward). `vslsp plan` and
`vslsp validate` used to read every file through unified-planning's PDDLReader, whose import alone
(its engines, ConfigSpace, SciPy) costs about 1.5 s, and then parsed the text a second time after
the checks. The language engine (:mod:`vslsp.symbolic.language`) has already read and checked the
files in one linear pass; :func:`read_with_engine` builds our :class:`~vslsp.symbolic.model.domain.Domain`
and :class:`~vslsp.symbolic.model.domain.Problem` from its tree when the files check clean and use only
what vslsp plans with (STRIPS, typing, negative and disjunctive conditions, equality, quantifiers,
conditional effects, PDDL 3.0 trajectory constraints). Anything else (an error, preferences,
``either`` types, functions, durative actions, derived predicates, a problem for another domain)
gives None, and the files go to unified-planning's reader, which then also words the errors. Both
give the same model (tests/symbolic/test_engine_reader.py reads every PDDL file of the repository
both ways).
"""

from __future__ import annotations

from vslsp.errors import InputError
from vslsp.symbolic.budget import check_instances, instance_count
from vslsp.symbolic.language import analyse
from vslsp.symbolic.language.syntax import Group, Token
from vslsp.symbolic.language.vocabulary import REQUIREMENTS
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
    bindings,
    conjunction,
    substitute,
)

#: The requirements the model covers (the others, numbers and time: the reader decides); ``:action-costs``
#: as (total-cost), read as action costs and left out as the reader does; ``:preferences`` because the
#: preferences themselves are removed from the text beforehand.
_REQUIREMENTS = frozenset(REQUIREMENTS) - {
    ":fluents",
    ":numeric-fluents",
    ":object-fluents",
    ":durative-actions",
    ":duration-inequalities",
    ":continuous-effects",
    ":derived-predicates",
    ":timed-initial-literals",
    ":domain-axioms",
    ":safety-constraints",
    ":expression-evaluation",
}
_DOMAIN_SECTIONS = frozenset((":requirements", ":types", ":constants", ":predicates", ":functions", ":action"))
_PROBLEM_SECTIONS = frozenset((":domain", ":requirements", ":objects", ":init", ":goal", ":constraints", ":metric"))
_COST = "total-cost"


class Unsupported(Exception):
    """Something the tree reader leaves to unified-planning's reader."""


def read_with_engine(
    domain_text: str, problem_text: str | None, domain_name: str = "<domain>", problem_name: str = "<problem>"
) -> tuple[Domain, Problem | None] | None:
    """The domain (and problem) of the texts, or None when they use what this reader leaves to
    unified-planning's (the module's list). Files with an error raise its :class:`InputError`, worded
    and placed as ``vslsp pddl check`` says it (the first; the count of the others after it), so
    that every command names a mistake at one place."""
    analysis = analyse(domain_text, domain_name, problem_text, problem_name)
    if analysis.errors:
        first, others = analysis.errors[0], len(analysis.errors) - 1
        more = f" ({others} more error{'s' if others > 1 else ''}: vslsp pddl check lists them all)" if others else ""
        raise InputError(first.format().replace(": error: ", ": ", 1) + more)
    if analysis.domain_name is None or (problem_text is not None and analysis.problem_name is None):
        return None
    try:
        domain = _domain(analysis.documents[domain_name].groups[0], analysis.domain_name.lower())
        if problem_text is None or analysis.problem_name is None:
            return domain, None
        problem = _problem(analysis.documents[problem_name].groups[0], analysis.problem_name.lower(), domain)
    except Unsupported:
        return None
    except InputError as error:  # a limit of the problem as a whole (its ground instances): no place in it
        raise InputError(f"{problem_name}: {error}") from None
    return domain, problem


# --- the domain ---------------------------------------------------------------------------------


def _sections(define: Group, allowed: frozenset[str]) -> list[Group]:
    found = []
    for item in define.items[2:]:
        if not isinstance(item, Group) or item.key not in allowed:
            raise Unsupported(item.key if isinstance(item, Group) else "text")
        found.append(item)
    return found


def _requirements(section: Group) -> None:
    for item in section.items[1:]:
        if not isinstance(item, Token) or item.key not in _REQUIREMENTS:
            raise Unsupported("requirement")


def _typed_names(items: list[Token | Group]) -> list[tuple[str, str]]:
    """``a b - t c`` as ``[(a, t), (b, t), (c, object)]`` (names in lower case)."""
    found: list[tuple[str, str]] = []
    pending: list[str] = []
    index = 0
    while index < len(items):
        item = items[index]
        if not isinstance(item, Token):
            raise Unsupported("either")  # (either a b) and anything else but names
        if item.text == "-":
            kind = items[index + 1] if index + 1 < len(items) else None
            if not isinstance(kind, Token):
                raise Unsupported("either")
            found.extend((name, kind.key) for name in pending)
            pending = []
            index += 2
            continue
        pending.append(item.key)
        index += 1
    return found + [(name, "object") for name in pending]


def _domain(define: Group, name: str) -> Domain:
    types: list[tuple[str, str | None]] = []
    constants: list[tuple[str, str]] = []
    predicates: list[Predicate] = []
    actions: list[Action] = []
    for section in _sections(define, _DOMAIN_SECTIONS):
        if section.key == ":requirements":
            _requirements(section)
        elif section.key == ":types":
            for type_name, parent in _typed_names(section.items[1:]):
                if type_name != "object":
                    types.append((type_name, None if parent == "object" else parent))
        elif section.key == ":constants":
            constants.extend(_typed_names(section.items[1:]))
        elif section.key == ":functions":  # only (total-cost) [- number]: action costs
            rest = section.items[1:]
            if not rest or not isinstance(rest[0], Group) or rest[0].key != _COST or len(rest[0].items) != 1:
                raise Unsupported("functions")
            if [i.key for i in rest[1:] if isinstance(i, Token)] not in ([], ["-", "number"]) or len(rest) not in (
                1,
                3,
            ):
                raise Unsupported("functions")
        elif section.key == ":predicates":
            for item in section.items[1:]:
                if not isinstance(item, Group) or item.head is None:
                    raise Unsupported("predicate")
                predicates.append(Predicate(item.key, tuple(_parameters(item.items[1:]))))
        else:
            actions.append(_action(section))
    _distinct_names(types, predicates, actions, constants)
    return Domain(name, _parents_first(types), tuple(predicates), tuple(actions), tuple(constants))


def _distinct_names(types, predicates, actions, objects) -> None:
    """Unsupported (the reader refuses it, saying so) when a name is given to two kinds of things."""
    kinds = [
        {t for t, _ in types} | {"object"},
        {p.name for p in predicates},
        {a.name for a in actions},
        {o for o, _ in objects},
    ]
    for i, names in enumerate(kinds):
        if any(names & other for other in kinds[i + 1 :]):
            raise Unsupported("a name given to two things")


def _parents_first(types: list[tuple[str, str | None]]) -> tuple[tuple[str, str | None], ...]:
    """The types, each declared once (its last declaration), every parent before its children."""
    parent = dict(types)
    ordered: list[tuple[str, str | None]] = []
    seen: set[str] = set()

    def add(type_name: str, trail: tuple[str, ...] = ()) -> None:
        if type_name in seen or type_name not in parent or type_name in trail:
            return
        above = parent[type_name]
        if above is not None:
            add(above, (*trail, type_name))
        seen.add(type_name)
        ordered.append((type_name, above))

    for type_name, _ in types:
        add(type_name)
    return tuple(ordered)


def _parameters(items: list[Token | Group]) -> list[tuple[str, str]]:
    return [(f"?{n.removeprefix('?')}", t) for n, t in _typed_names(items)]


def _action(section: Group) -> Action:
    items = section.items[1:]
    if not items or not isinstance(items[0], Token):
        raise Unsupported("action")
    name = items[0].key
    parts: dict[str, Token | Group] = {}
    index = 1
    while index + 1 < len(items):
        key = items[index]
        if not isinstance(key, Token) or key.key not in (":parameters", ":precondition", ":effect"):
            raise Unsupported("action part")
        parts[key.key] = items[index + 1]
        index += 2
    if index != len(items):
        raise Unsupported("action part")
    parameters: list[tuple[str, str]] = []
    if ":parameters" in parts:
        group = parts[":parameters"]
        if not isinstance(group, Group):
            raise Unsupported("parameters")
        parameters = _parameters(group.items)
    precondition: Formula = And(())
    if ":precondition" in parts:
        precondition = conjunction([_formula(parts[":precondition"])])  # its top-level and, as the reader's
    effects = tuple(_effects(parts[":effect"], (), And(()))) if ":effect" in parts else ()
    return Action(name, tuple(parameters), precondition, effects)


def _effects(node: Token | Group, variables: tuple[tuple[str, str], ...], condition: Formula) -> list[Effect]:
    if not isinstance(node, Group):
        raise Unsupported("effect")
    if node.key == "and":
        return [e for item in node.items[1:] for e in _effects(item, variables, condition)]
    if node.key == "increase" and len(node.items) == 3 and isinstance(node.items[1], Group):
        if node.items[1].key == _COST and len(node.items[1].items) == 1:
            return []  # an action's cost: left out (vslsp plans for the goal and the constraints)
    if node.key == "forall":
        if len(node.items) != 3 or not isinstance(node.items[1], Group):
            raise Unsupported("forall effect")
        bound = tuple(_parameters(node.items[1].items))
        return _effects(node.items[2], (*variables, *bound), condition)
    if node.key == "when":
        if len(node.items) != 3 or not isinstance(condition, And) or condition.args:
            raise Unsupported("nested when")
        return _effects(node.items[2], variables, _formula(node.items[1]))
    literal = _literal(node)
    if not variables and isinstance(condition, And) and not condition.args:
        return [literal]
    return [When(condition, (literal,), variables)]


def _literal(node: Group) -> Atom | Not:
    if node.key == "not":
        if len(node.items) != 2 or not isinstance(node.items[1], Group):
            raise Unsupported("literal")
        return Not(_atom(node.items[1]))
    return _atom(node)


def _atom(node: Group) -> Atom:
    if node.head is None or node.key in _OPERATORS:
        raise Unsupported("atom")
    args = node.items[1:]
    if not all(isinstance(a, Token) for a in args):
        raise Unsupported("atom")
    return Atom(node.key, tuple(_term(a) for a in args))  # type: ignore[arg-type]


def _term(token: Token) -> str:
    return f"?{token.key[1:]}" if token.key.startswith("?") else token.key


_OPERATORS = frozenset(("and", "or", "not", "imply", "forall", "exists", "=", "when", "preference"))


def _formula(node: Token | Group) -> Formula:
    if not isinstance(node, Group):
        raise Unsupported("formula")
    key, items = node.key, node.items[1:]
    if key == "and":
        return And(tuple(_formula(i) for i in items))
    if key == "or":
        return Or(tuple(_formula(i) for i in items))
    if key == "not":
        if len(items) != 1:
            raise Unsupported("not")
        return Not(_formula(items[0]))
    if key == "imply":
        if len(items) != 2:
            raise Unsupported("imply")
        return Imply(_formula(items[0]), _formula(items[1]))
    if key in ("forall", "exists"):
        if len(items) != 2 or not isinstance(items[0], Group):
            raise Unsupported(key)
        return (Forall if key == "forall" else Exists)(tuple(_parameters(items[0].items)), _formula(items[1]))
    if key == "=":
        if len(items) != 2 or not all(isinstance(i, Token) for i in items):
            raise Unsupported("=")
        return Equals(_term(items[0]), _term(items[1]))  # type: ignore[arg-type]
    return _atom(node)


# --- the problem --------------------------------------------------------------------------------


def _problem(define: Group, name: str, domain: Domain) -> Problem:
    objects: list[tuple[str, str]] = []
    init: list[Atom] = []
    goal: Formula = And(())
    constraints: list[Constraint] = []
    for section in _sections(define, _PROBLEM_SECTIONS):
        if section.key == ":domain":
            written = section.items[1] if len(section.items) == 2 else None
            if not isinstance(written, Token) or written.key != domain.name:
                raise Unsupported("another domain")  # the reader's path says so (a warning or exit 2)
        elif section.key == ":requirements":
            _requirements(section)
        elif section.key == ":objects":
            constants = set(domain.constants)
            objects.extend(o for o in _typed_names(section.items[1:]) if o not in constants)
        elif section.key == ":metric":  # only (minimize (total-cost)): left out, as the reader's path does
            words = [i.key for i in section.items[1:] if isinstance(i, Token)]
            costs = [i for i in section.items[1:] if isinstance(i, Group)]
            if words != ["minimize"] or len(costs) != 1 or costs[0].key != _COST or len(costs[0].items) != 1:
                raise Unsupported("metric")
        elif section.key == ":init":
            for item in section.items[1:]:
                if not isinstance(item, Group):
                    raise Unsupported("init")
                if item.key == "=" and len(item.items) == 3 and isinstance(item.items[1], Group):
                    if item.items[1].key == _COST:
                        continue  # (= (total-cost) 0)
                if item.key == "not":
                    _literal(item)  # a negative initial literal says what the closed world says
                    continue
                init.append(_atom(item))
        elif section.key == ":goal":
            if len(section.items) != 2:
                raise Unsupported("goal")
            goal = conjunction([_formula(section.items[1])])
        else:
            problem = Problem(name, domain, tuple(objects), frozenset(init), goal)
            universe = problem.universe()
            for item in section.items[1:]:
                count, variables = _constraint_instances(item, universe)  # before any is built
                check_instances(count, f"the constraint (forall ({variables}) ...)" if variables else "a constraint")
                constraints.extend(_constraints(item, {}, problem))
    _distinct_names(domain.types, domain.predicates, domain.actions, objects)
    return Problem(name, domain, tuple(objects), frozenset(init), goal, tuple(constraints))


def _constraint_instances(node: Token | Group, universe: Universe) -> tuple[int, str]:
    """How many constraints one item of ``(:constraints ...)`` stands for once its ``forall`` are written
    out (counted without writing them, without recursion), and the variables of the largest, as
    :func:`vslsp.symbolic.model.up_model.problem_from_up` counts them."""
    total, most, variables_of_most = 0, 0, ""
    stack: list[tuple[Token | Group, int]] = [(node, 1)]
    while stack:
        current, factor = stack.pop()
        if isinstance(current, Group) and current.key == "and":
            stack.extend((item, factor) for item in current.items[1:])
        elif isinstance(current, Group) and current.key == "forall" and len(current.items) == 3:
            head = current.items[1]
            variables = tuple(_parameters(head.items)) if isinstance(head, Group) else ()
            inner = factor * instance_count(variables, universe)
            if inner > most:
                most, variables_of_most = inner, " ".join(f"{v} - {t}" for v, t in variables)
            stack.append((current.items[2], inner))
        else:
            total += factor
    return total, variables_of_most


def _constraints(node: Token | Group, binding: dict[str, str], problem: Problem) -> list[Constraint]:
    """Trajectory constraints of one item of ``(:constraints ...)``; a ``forall`` around constraints
    expanded over the objects (as :func:`vslsp.symbolic.model.up_model.problem_from_up` does)."""
    if not isinstance(node, Group):
        raise Unsupported("constraint")
    key, items = node.key, node.items[1:]
    if key == "and":
        return [c for item in items for c in _constraints(item, binding, problem)]
    if key == "forall":
        if len(items) != 2 or not isinstance(items[0], Group):
            raise Unsupported("forall constraint")
        variables = tuple(_parameters(items[0].items))
        return [
            c
            for extra in bindings(variables, problem.universe())
            for c in _constraints(items[1], {**binding, **extra}, problem)
        ]
    formulas = [substitute(_formula(item), binding) for item in items]
    if key == "sometime-after" and len(formulas) == 2 and formulas[0] == And(()):
        return [AtEnd(formulas[1])]  # (at end φ), as the reader is handed it
    kinds: dict[str, type[Always | Sometime | AtMostOnce]] = {
        "always": Always,
        "sometime": Sometime,
        "at-most-once": AtMostOnce,
    }
    if key in kinds and len(formulas) == 1:
        return [kinds[key](formulas[0])]
    pairs: dict[str, type[SometimeBefore | SometimeAfter]] = {
        "sometime-before": SometimeBefore,
        "sometime-after": SometimeAfter,
    }
    if key in pairs and len(formulas) == 2:
        return [pairs[key](formulas[0], formulas[1])]
    raise Unsupported(key)
