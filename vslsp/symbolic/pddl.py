"""PDDL 3.0 files through unified-planning: our domains/problems to and from UP's model.

Paper: "Implementation" (VSL-SP writes the learned actions to the planner's domain file and
the demonstrated order as PDDL 3.0 constraints of the problem file). Reading and writing is
unified-planning's PDDLReader/PDDLWriter; this module converts between its model and ours,
and turns its parse errors into :class:`~vslsp.errors.InputError` with FILE:LINE:COL.
unified-planning is imported lazily, so ``import vslsp.symbolic`` stays light.
"""

from __future__ import annotations

import re
import warnings
from collections import OrderedDict
from dataclasses import replace
from functools import lru_cache
from pathlib import Path

from vslsp.errors import InputError
from vslsp.symbolic.formula import (
    Always,
    And,
    AtEnd,
    AtMostOnce,
    Atom,
    Constraint,
    Exists,
    Forall,
    Formula,
    Imply,
    Not,
    Or,
    Sometime,
    SometimeAfter,
    SometimeBefore,
    conjunction,
    constraint_formulas,
    expand_quantifiers,
    substitute,
)
from vslsp.symbolic.model import Action, Domain, Predicate, Problem
from vslsp.symbolic.pddl_errors import check_domain_name, check_text, located_error


@lru_cache(maxsize=1)
def environment():
    """unified-planning's global environment, credits banner silenced."""
    from unified_planning.shortcuts import get_environment

    env = get_environment()
    env.credits_stream = None
    return env


# --- ours -> unified-planning ------------------------------------------------------------

def to_up(domain: Domain, problem: Problem | None = None, expand: bool = False):
    """A ``unified_planning.model.Problem`` for ``domain`` (and ``problem``'s objects, init, goal, constraints).

    ``expand``: quantifiers of the goal and the constraints written out over the objects (for planners).
    """
    from unified_planning.model import Fluent, InstantaneousAction, Object, Variable
    from unified_planning.model import Problem as UPProblem

    env = environment()
    em, tm = env.expression_manager, env.type_manager
    parents = dict(domain.types)
    types: dict = {}

    def user_type(name: str):
        if name == "object" and name not in parents:
            return user_type_object()
        if name not in types:
            if name not in parents:
                raise InputError(f"undefined type {name!r} in domain {domain.name}")
            parent = parents[name]
            types[name] = tm.UserType(name, user_type(parent) if parent else None)
        return types[name]

    def user_type_object():
        if "object" not in types:
            types["object"] = tm.UserType("object")
        return types["object"]

    up_problem = UPProblem(domain.name, env, initial_defaults={tm.BoolType(): em.FALSE()})
    for name, _ in domain.types:
        user_type(name)
    fluents = {}
    for predicate in domain.predicates:
        fluents[predicate.name] = Fluent(predicate.name, tm.BoolType(),
                                         OrderedDict((p.lstrip("?"), user_type(t)) for p, t in predicate.parameters), env)
        up_problem.add_fluent(fluents[predicate.name], default_initial_value=False)
    objects = {}
    if problem is not None:
        for name, type_ in problem.objects:
            objects[name] = Object(name, user_type(type_), env)
            up_problem.add_object(objects[name])

    def term(arg: str, scope: dict):
        if arg in scope:
            return scope[arg]
        if arg.startswith("?"):
            raise InputError(f"variable {arg} is not a parameter or a quantified variable")
        if arg not in objects:
            raise InputError(f"{arg!r} is not an object of the problem")
        return em.ObjectExp(objects[arg])

    def node(formula: Formula, scope: dict):
        if isinstance(formula, Atom):
            if formula.predicate not in fluents:
                raise InputError(f"unknown predicate {formula.predicate!r} in {formula.to_pddl()}")
            return em.FluentExp(fluents[formula.predicate], [term(a, scope) for a in formula.args])
        if isinstance(formula, Not):
            return em.Not(node(formula.arg, scope))
        if isinstance(formula, And):
            return em.And([node(a, scope) for a in formula.args])
        if isinstance(formula, Or):
            return em.Or([node(a, scope) for a in formula.args])
        if isinstance(formula, Imply):
            return em.Implies(node(formula.condition, scope), node(formula.consequence, scope))
        variables = [Variable(v.lstrip("?"), user_type(t), env) for v, t in formula.variables]
        inner = {**scope, **{v: em.VariableExp(var) for (v, _), var in zip(formula.variables, variables)}}
        body = node(formula.body, inner)
        return em.Forall(body, *variables) if isinstance(formula, Forall) else em.Exists(body, *variables)

    for action in domain.actions:
        up_action = InstantaneousAction(action.name, OrderedDict((p.lstrip("?"), user_type(t)) for p, t in action.parameters), env)
        scope = {p: em.ParameterExp(up_action.parameter(p.lstrip("?"))) for p, _ in action.parameters}
        if action.precondition != And(()):
            up_action.add_precondition(node(action.precondition, scope))
        for effect in action.effects:
            atom, value = (effect.arg, False) if isinstance(effect, Not) else (effect, True)
            up_action.add_effect(node(atom, scope), value)
        up_problem.add_action(up_action)
    if problem is None:
        return up_problem

    if expand:
        universe = problem.universe()
        problem = replace(problem, goal=expand_quantifiers(problem.goal, universe), constraints=tuple(
            type(c)(*(expand_quantifiers(f, universe) for f in constraint_formulas(c))) for c in problem.constraints))
    for atom in sorted(problem.init, key=lambda a: (a.predicate, a.args)):
        up_problem.set_initial_value(node(atom, {}), True)
    at_end = [c.formula for c in problem.constraints if isinstance(c, AtEnd)]
    goal = conjunction([problem.goal, *at_end]) if at_end else problem.goal
    if goal != And(()):
        up_problem.add_goal(node(goal, {}))
    trajectory = []
    operators = {Always: em.Always, Sometime: em.Sometime, AtMostOnce: em.AtMostOnce,
                 SometimeBefore: em.SometimeBefore, SometimeAfter: em.SometimeAfter}
    for constraint in problem.constraints:
        if not isinstance(constraint, AtEnd):
            parts = [node(f, {}) for f in constraint_formulas(constraint)]
            trajectory.append(operators[type(constraint)](*parts))
    if trajectory:
        up_problem.add_trajectory_constraint(em.And(trajectory) if len(trajectory) > 1 else trajectory[0])
    return up_problem


# --- writing -------------------------------------------------------------------------------

def write_domain(domain: Domain) -> str:
    """The domain as PDDL text, with the ``:constraints`` requirement (problems may order it)."""
    from unified_planning.io import PDDLWriter

    text = PDDLWriter(to_up(domain)).get_domain()
    text = re.sub(r"\(domain [^)\s]+\)", f"(domain {domain.name})", text, count=1)
    if ":constraints" not in text:
        text = text.replace(" (:requirements :strips", " (:requirements :strips :constraints", 1)
    return text


def write_problem(problem: Problem) -> str:
    """The problem as PDDL text; each trajectory constraint on its own line under ``:constraints``."""
    from unified_planning.io import PDDLWriter

    text = PDDLWriter(to_up(problem.domain, problem)).get_problem()
    text = re.sub(r"\(define \(problem [^)\s]+\)", f"(define (problem {problem.name})", text, count=1)
    text = re.sub(r"\(:domain [^)\s]+\)", f"(:domain {problem.domain.name})", text, count=1)
    for section in (":goal", ":constraints"):
        text = _one_item_per_line(text, section)
    return text


def _one_item_per_line(text: str, section: str) -> str:
    """The writer's `` (section (and A B))`` laid out with A and B on lines of their own."""
    start = text.find(f" ({section} ")
    if start < 0:
        return text
    depth, end = 0, start
    for end in range(start + 1, len(text)):
        depth += {"(": 1, ")": -1}.get(text[end], 0)
        if depth == 0:
            break
    body = re.sub(r"\(\s+", "(", re.sub(r"\s+\)", ")", " ".join(text[start + len(section) + 3:end].split())))
    items = _top_level(body[len("(and "):-1]) if body.startswith("(and ") else [body]
    layout = f" ({section} (and\n" + "".join(f"   {item}\n" for item in items) + " ))" if len(items) > 1 \
        else f" ({section} {items[0] if items else body})"
    return text[:start] + layout + text[end + 1:]


def _top_level(text: str) -> list[str]:
    """The parenthesised expressions side by side in ``text``."""
    items, depth, start = [], 0, 0
    for index, char in enumerate(text):
        if char == "(":
            start = index if depth == 0 else start
            depth += 1
        elif char == ")":
            depth -= 1
            if depth == 0:
                items.append(text[start:index + 1])
    return items


def save(text: str, path: str | Path) -> Path:
    """Write PDDL ``text`` to ``path`` (folders created)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    return path


# --- reading -------------------------------------------------------------------------------

def read_pddl(domain_path: str | Path, problem_path: str | Path | None = None) -> tuple[Domain, Problem | None]:
    """Read a domain (and a problem) file through unified-planning's PDDLReader.

    Malformed input raises InputError ``FILE:LINE:COL: what is wrong``.
    """
    domain_text = _read_text(domain_path)
    domain = domain_from_up(_parse(domain_text, None, str(domain_path), None))
    if problem_path is None:
        return domain, None
    problem_text = _read_text(problem_path)
    up_problem = _parse(domain_text, problem_text, str(domain_path), str(problem_path))
    check_domain_name(problem_text, domain.name, str(problem_path))
    return domain, problem_from_up(up_problem, domain)


def read_domain(path: str | Path) -> Domain:
    return read_pddl(path)[0]


def read_problem(domain_path: str | Path, problem_path: str | Path) -> Problem:
    problem = read_pddl(domain_path, problem_path)[1]
    assert problem is not None
    return problem


def parse_pddl(domain_text: str, problem_text: str | None = None) -> tuple[Domain, Problem | None]:
    """:func:`read_pddl` on strings (errors name ``<domain>`` / ``<problem>``)."""
    domain = domain_from_up(_parse(domain_text, None, "<domain>", None))
    if problem_text is None:
        return domain, None
    up_problem = _parse(domain_text, problem_text, "<domain>", "<problem>")
    check_domain_name(problem_text, domain.name, "<problem>")
    return domain, problem_from_up(up_problem, domain)


def _read_text(path: str | Path) -> str:
    try:
        return Path(path).read_text(encoding="utf-8-sig")
    except OSError as error:
        raise InputError(f"{path}: cannot read the file ({error.strerror})") from None


def _parse(domain_text: str, problem_text: str | None, domain_name: str, problem_name: str | None):
    from unified_planning.io import PDDLReader

    text, name = (problem_text, problem_name) if problem_text is not None else (domain_text, domain_name)
    check_text(text, name)
    try:
        with warnings.catch_warnings():  # pyparsing's deprecation notes about the reader's own calls
            warnings.simplefilter("ignore", DeprecationWarning)
            return PDDLReader(environment()).parse_problem_string(domain_text, problem_text)
    except Exception as error:  # UP raises SyntaxError, pyparsing and UP exceptions alike
        raise located_error(error, text, name) from None


# --- unified-planning -> ours --------------------------------------------------------------

def domain_from_up(up_problem) -> Domain:
    """Our Domain from a UP problem read from a domain file."""
    types = tuple((t.name, t.father.name if t.father is not None else None) for t in up_problem.user_types)
    predicates = []
    for fluent in up_problem.fluents:
        if not fluent.type.is_bool_type():
            raise InputError(f"function {fluent.name} is numeric; vslsp domains have Boolean predicates only")
        predicates.append(Predicate(fluent.name, tuple((f"?{p.name}", p.type.name) for p in fluent.signature)))
    actions = []
    for up_action in up_problem.actions:
        if not hasattr(up_action, "preconditions"):
            raise InputError(f"action {up_action.name} is durative; vslsp domains have instantaneous actions only")
        effects = []
        for effect in up_action.effects:
            if effect.is_conditional() or effect.is_forall() or not effect.value.is_bool_constant():
                raise InputError(f"action {up_action.name}: effect {effect} is not a literal; "
                                 "vslsp actions have literal effects only")
            atom = formula_from_up(effect.fluent)
            effects.append(atom if effect.value.is_true() else Not(atom))
        actions.append(Action(
            up_action.name,
            tuple((f"?{p.name}", p.type.name) for p in up_action.parameters),
            conjunction([formula_from_up(c) for c in up_action.preconditions]) if up_action.preconditions else And(()),
            tuple(effects),
        ))
    return Domain(up_problem.name, types, tuple(predicates), tuple(actions))


def problem_from_up(up_problem, domain: Domain) -> Problem:
    """Our Problem from a UP problem read from a domain and a problem file."""
    objects = tuple((o.name, o.type.name) for o in up_problem.all_objects)
    init = frozenset(formula_from_up(f) for f, v in up_problem.explicit_initial_values.items() if v.is_true())
    goal = conjunction([formula_from_up(g) for g in up_problem.goals]) if up_problem.goals else And(())
    problem = Problem(up_problem.name, domain, objects, init, goal)
    constraints: list[Constraint] = []
    for node in up_problem.trajectory_constraints:
        constraints.extend(_constraints_from_up(node, {}, problem))
    return Problem(up_problem.name, domain, objects, init, goal, tuple(constraints))


def formula_from_up(node) -> Formula:
    """Our formula from a UP FNode (parameters and variables become ``?name``)."""
    if node.is_fluent_exp():
        return Atom(node.fluent().name, tuple(_term_from_up(a) for a in node.args))
    if node.is_not():
        return Not(formula_from_up(node.arg(0)))
    if node.is_and():
        return And(tuple(formula_from_up(a) for a in node.args))
    if node.is_or():
        return Or(tuple(formula_from_up(a) for a in node.args))
    if node.is_implies():
        return Imply(formula_from_up(node.arg(0)), formula_from_up(node.arg(1)))
    if node.is_forall() or node.is_exists():
        variables = tuple((f"?{v.name}", v.type.name) for v in node.variables())
        return (Forall if node.is_forall() else Exists)(variables, formula_from_up(node.arg(0)))
    if node.is_true():
        return And(())
    if node.is_false():
        return Or(())
    raise InputError(f"{node} is not supported: vslsp formulas use and, or, not, imply, forall, exists "
                     "and predicates (no equality or numbers)")


def _term_from_up(node) -> str:
    if node.is_parameter_exp():
        return f"?{node.parameter().name}"
    if node.is_variable_exp():
        return f"?{node.variable().name}"
    if node.is_object_exp():
        return node.object().name
    raise InputError(f"{node} is not an object, parameter or variable")


_UP_CONSTRAINTS = (("is_always", Always), ("is_sometime", Sometime), ("is_at_most_once", AtMostOnce),
                   ("is_sometime_before", SometimeBefore), ("is_sometime_after", SometimeAfter))


def _constraints_from_up(node, binding: dict, problem: Problem) -> list[Constraint]:
    """Trajectory constraints from a UP node; a ``forall`` around constraints is expanded over the objects."""
    if node.is_and():
        return [c for a in node.args for c in _constraints_from_up(a, binding, problem)]
    if node.is_forall():
        from vslsp.symbolic.formula import _bindings

        variables = tuple((f"?{v.name}", v.type.name) for v in node.variables())
        return [c for extra in _bindings(variables, problem.universe())
                for c in _constraints_from_up(node.arg(0), {**binding, **extra}, problem)]
    for test, kind in _UP_CONSTRAINTS:
        if getattr(node, test)():
            return [kind(*(substitute(formula_from_up(a), binding) for a in node.args))]
    raise InputError(f"{node} is not a PDDL 3.0 trajectory constraint")
