"""Our PDDL model to and from unified-planning's model (``unified_planning.model``).

Paper: "Implementation" (the learned domain and the task go to an off-the-shelf planner).
This adapter is the only place that builds or reads unified-planning model objects; it does
not import unified-planning's engines (:mod:`vslsp.symbolic.engines.planner` does) nor its PDDL
reader (:mod:`vslsp.symbolic.io.pddl` does). unified-planning is imported lazily.
"""

from __future__ import annotations

from collections import OrderedDict
from dataclasses import replace
from functools import lru_cache
from typing import Any

from vslsp.errors import InputError
from vslsp.symbolic.budget import check_instances, instance_count
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
    constraint_formulas,
    expand_quantifiers,
    substitute,
)


@lru_cache(maxsize=1)
def environment() -> Any:
    """unified-planning's global environment, credits banner silenced."""
    from unified_planning.shortcuts import get_environment

    env = get_environment()
    env.credits_stream = None
    return env


# --- ours -> unified-planning ------------------------------------------------------------


def to_up(domain: Domain, problem: Problem | None = None, expand: bool = False) -> Any:
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
        if name not in types:
            if name == "object" and name not in parents:
                types[name] = tm.UserType("object")
                return types[name]
            if name not in parents:
                raise InputError(f"undefined type {name!r} in domain {domain.name}")
            parent = parents[name]
            types[name] = tm.UserType(name, user_type(parent) if parent else None)
        return types[name]

    up_problem = UPProblem(domain.name, env, initial_defaults={tm.BoolType(): em.FALSE()})
    for name, _ in domain.types:
        user_type(name)
    fluents = {}
    for predicate in domain.predicates:
        signature = OrderedDict((p.lstrip("?"), user_type(t)) for p, t in predicate.parameters)
        fluents[predicate.name] = Fluent(predicate.name, tm.BoolType(), signature, env)
        up_problem.add_fluent(fluents[predicate.name], default_initial_value=False)
    objects = {}
    for name, type_ in problem.all_objects() if problem is not None else domain.constants:
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
        if isinstance(formula, Equals):
            return em.Equals(term(formula.left, scope), term(formula.right, scope))
        if isinstance(formula, Not):
            return em.Not(node(formula.arg, scope))
        if isinstance(formula, And):
            return em.And([node(a, scope) for a in formula.args])
        if isinstance(formula, Or):
            return em.Or([node(a, scope) for a in formula.args])
        if isinstance(formula, Imply):
            return em.Implies(node(formula.condition, scope), node(formula.consequence, scope))
        variables = [Variable(v.lstrip("?"), user_type(t), env) for v, t in formula.variables]
        inner = {**scope, **{v: em.VariableExp(var) for (v, _), var in zip(formula.variables, variables, strict=False)}}
        body = node(formula.body, inner)
        return em.Forall(body, *variables) if isinstance(formula, Forall) else em.Exists(body, *variables)

    for action in domain.actions:
        parameters = OrderedDict((p.lstrip("?"), user_type(t)) for p, t in action.parameters)
        up_action = InstantaneousAction(action.name, parameters, env)
        scope = {p: em.ParameterExp(up_action.parameter(p.lstrip("?"))) for p, _ in action.parameters}
        if action.precondition != And(()):
            up_action.add_precondition(node(action.precondition, scope))
        for effect in action.effects:
            if not isinstance(effect, When):
                atom, value = (effect.arg, False) if isinstance(effect, Not) else (effect, True)
                up_action.add_effect(node(atom, scope), value)  # type: ignore[arg-type]
                continue
            variables = [Variable(v.lstrip("?"), user_type(t), env) for v, t in effect.variables]
            bound = zip(effect.variables, variables, strict=True)
            inner = {**scope, **{v: em.VariableExp(var) for (v, _), var in bound}}
            condition = node(effect.condition, inner)
            for literal_ in effect.effects:
                atom, value = (literal_.arg, False) if isinstance(literal_, Not) else (literal_, True)
                up_action.add_effect(node(atom, inner), value, condition, forall=variables)  # type: ignore[arg-type]
        up_problem.add_action(up_action)
    if problem is None:
        return up_problem

    if expand:
        universe = problem.universe()
        problem = replace(
            problem,
            goal=expand_quantifiers(problem.goal, universe, "the goal"),
            constraints=tuple(
                type(c)(
                    *(
                        expand_quantifiers(f, universe, f"the constraint {_short(c.to_pddl())}")
                        for f in constraint_formulas(c)
                    )
                )
                for c in problem.constraints
            ),
        )
    for atom in sorted(problem.init, key=lambda a: (a.predicate, a.args)):
        up_problem.set_initial_value(node(atom, {}), True)
    at_end = [c.formula for c in problem.constraints if isinstance(c, AtEnd)]
    goal = conjunction([problem.goal, *at_end]) if at_end else problem.goal
    if goal != And(()):
        up_problem.add_goal(node(goal, {}))
    trajectory = []
    operators = {
        Always: em.Always,
        Sometime: em.Sometime,
        AtMostOnce: em.AtMostOnce,
        SometimeBefore: em.SometimeBefore,
        SometimeAfter: em.SometimeAfter,
    }
    for constraint in problem.constraints:
        if not isinstance(constraint, AtEnd):
            parts = [node(f, {}) for f in constraint_formulas(constraint)]
            trajectory.append(operators[type(constraint)](*parts))
    if trajectory:
        up_problem.add_trajectory_constraint(em.And(trajectory) if len(trajectory) > 1 else trajectory[0])
    return up_problem


# --- unified-planning -> ours --------------------------------------------------------------


def domain_from_up(up_problem: Any) -> Domain:
    """Our Domain from a UP problem read from a domain file (its objects are the domain's constants)."""
    types = tuple((t.name, t.father.name if t.father is not None else None) for t in up_problem.user_types)
    predicates = []
    for fluent in up_problem.fluents:
        if not fluent.type.is_bool_type():
            raise InputError(
                f"function {fluent.name} is numeric; vslsp domains have Boolean predicates only "
                "(total-cost is read as action costs and ignored)"
            )
        predicates.append(Predicate(fluent.name, tuple((f"?{p.name}", p.type.name) for p in fluent.signature)))
    actions = []
    for up_action in up_problem.actions:
        if not hasattr(up_action, "preconditions"):
            raise InputError(f"action {up_action.name} is durative; vslsp domains have instantaneous actions only")
        effects: list[Effect] = []
        for effect in up_action.effects:
            if not effect.is_assignment() or not effect.value.is_bool_constant():
                raise InputError(f"action {up_action.name}: effect {effect} is numeric; vslsp actions set predicates")
            atom = formula_from_up(effect.fluent)
            literal_ = atom if effect.value.is_true() else Not(atom)
            if effect.is_conditional() or effect.is_forall():
                variables = tuple((f"?{v.name}", v.type.name) for v in effect.forall)
                condition = formula_from_up(effect.condition) if effect.is_conditional() else And(())
                effects.append(When(condition, (literal_,), variables))  # type: ignore[arg-type]
            else:
                effects.append(literal_)  # type: ignore[arg-type]
        actions.append(
            Action(
                up_action.name,
                tuple((f"?{p.name}", p.type.name) for p in up_action.parameters),
                conjunction([formula_from_up(c) for c in up_action.preconditions])
                if up_action.preconditions
                else And(()),
                tuple(effects),
            )
        )
    constants = tuple((o.name, o.type.name) for o in up_problem.all_objects)
    return Domain(up_problem.name, types, tuple(predicates), tuple(actions), constants)


def problem_from_up(up_problem: Any, domain: Domain) -> Problem:
    """Our Problem from a UP problem read from a domain and a problem file."""
    constants = set(domain.constants)
    objects = tuple(o for o in ((o.name, o.type.name) for o in up_problem.all_objects) if o not in constants)
    init = frozenset(
        formula_from_up(f)
        for f, v in up_problem.explicit_initial_values.items()
        if v.is_bool_constant() and v.is_true()
    )
    goal = conjunction([formula_from_up(g) for g in up_problem.goals]) if up_problem.goals else And(())
    problem = Problem(up_problem.name, domain, objects, init, goal)
    universe = problem.universe()
    constraints: list[Constraint] = []
    for node in up_problem.trajectory_constraints:
        count, variables = _constraint_instances(node, universe)
        check_instances(count, f"the constraint (forall ({variables}) ...)" if variables else "a constraint")
        constraints.extend(_constraints_from_up(node, {}, universe))
    return Problem(up_problem.name, domain, objects, init, goal, tuple(constraints))


def _short(text: str, length: int = 80) -> str:
    """``text`` cut to ``length`` characters for a message."""
    return text if len(text) <= length else text[: length - 3] + "..."


def _constraint_instances(node: Any, universe: Universe) -> tuple[int, str]:
    """How many constraints a UP trajectory-constraint node stands for once its ``forall`` are written out
    (counted without writing them, without recursion), and the variables of the largest (``?a - t ...``)."""
    total, most, variables_of_most = 0, 0, ""
    stack = [(node, 1)]
    while stack:
        current, factor = stack.pop()
        if current.is_and():
            stack.extend((arg, factor) for arg in current.args)
        elif current.is_forall():
            variables = tuple((f"?{v.name}", v.type.name) for v in current.variables())
            inner = factor * instance_count(variables, universe)
            if inner > most:
                most, variables_of_most = inner, " ".join(f"{v} - {t}" for v, t in variables)
            stack.append((current.arg(0), inner))
        elif not current.is_true():
            total += factor
    return total, variables_of_most


def formula_from_up(node: Any) -> Formula:
    """Our formula from a UP FNode (parameters and variables become ``?name``)."""
    if node.is_fluent_exp():
        return Atom(node.fluent().name, tuple(_term_from_up(a) for a in node.args))
    if node.is_equals():
        return Equals(_term_from_up(node.arg(0)), _term_from_up(node.arg(1)))
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
    raise InputError(
        f"{_as_written(node)} is not supported: vslsp formulas use and, or, not, imply, forall, "
        "exists, = and predicates (no numbers)"
    )


def _as_written(node: Any) -> str:
    """A UP expression in PDDL spelling, for messages (best effort)."""
    if node.is_fluent_exp() or node.is_parameter_exp() or node.is_variable_exp() or node.is_object_exp():
        return str(node) if not node.is_fluent_exp() else f"({node.fluent().name} {' '.join(map(str, node.args))})"
    words = {"is_lt": "<", "is_le": "<=", "is_plus": "+", "is_minus": "-", "is_times": "*", "is_div": "/"}
    for test, word in words.items():
        if getattr(node, test, lambda: False)():
            return f"({word} {' '.join(_as_written(a) for a in node.args)})"
    return str(node)


def _term_from_up(node: Any) -> str:
    if node.is_parameter_exp():
        return f"?{node.parameter().name}"
    if node.is_variable_exp():
        return f"?{node.variable().name}"
    if node.is_object_exp():
        return node.object().name
    raise InputError(f"{_as_written(node)} is not an object, parameter or variable")


_UP_CONSTRAINTS = (
    ("is_always", Always),
    ("is_sometime", Sometime),
    ("is_at_most_once", AtMostOnce),
    ("is_sometime_before", SometimeBefore),
    ("is_sometime_after", SometimeAfter),
)


def _constraints_from_up(node: Any, binding: dict, universe: Universe) -> list[Constraint]:
    """Trajectory constraints from a UP node; a ``forall`` around constraints is expanded over the objects.

    ``(sometime-after true φ)`` is how the reader is handed ``(at end φ)`` (the same meaning).
    """
    if node.is_and():
        return [c for a in node.args for c in _constraints_from_up(a, binding, universe)]
    if node.is_true():
        return []
    if node.is_forall():
        variables = tuple((f"?{v.name}", v.type.name) for v in node.variables())
        return [
            c
            for extra in bindings(variables, universe)
            for c in _constraints_from_up(node.arg(0), {**binding, **extra}, universe)
        ]
    if node.is_sometime_after() and node.arg(0).is_true():
        return [AtEnd(substitute(formula_from_up(node.arg(1)), binding))]
    for test, kind in _UP_CONSTRAINTS:
        if getattr(node, test)():
            return [kind(*(substitute(formula_from_up(a), binding) for a in node.args))]  # type: ignore[arg-type]
    raise InputError(f"{_as_written(node)} is not a PDDL 3.0 trajectory constraint")
