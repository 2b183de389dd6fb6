"""Checking formulas: preconditions and goals (goal descriptions), effects, the initial state,
PDDL 3.0 constraints and the metric. Every name is resolved to its declaration (a reference in the
index) or reported where it is written, with the declared name closest to it.
"""

from __future__ import annotations

from vslsp.symbolic.language.context import Context
from vslsp.symbolic.language.declarations import Body, parameters
from vslsp.symbolic.language.diagnostics import Fix, Span
from vslsp.symbolic.language.index import Declaration
from vslsp.symbolic.language.syntax import Group, Token
from vslsp.symbolic.language.vocabulary import (
    ARITHMETIC,
    COMPARISONS,
    EFFECT_OPERATORS,
    GOAL_OPERATORS,
    NOT_PDDL,
    NUMERIC_EFFECTS,
    PDDL3_NAMES,
    PDDL3_OPERATORS,
    TIMED_OPERATORS,
)

Scope = dict[str, Declaration]


def check_body(ctx: Context, body: Body) -> None:
    if body.role in ("precondition", "goal"):
        goal(ctx, body.node, body.scope, body.role)
    elif body.role == "effect":
        effect(ctx, body.node, body.scope)
    elif body.role == "constraints":
        constraint(ctx, body.node, body.scope)
    elif body.role == "init" and isinstance(body.node, Group):
        init(ctx, body.node)
    elif body.role == "metric":
        numeric(ctx, body.node, body.scope)


def _quantified(ctx: Context, node: Group, scope: Scope) -> tuple[Scope, Token | Group | None]:
    """The scope inside ``(forall|exists (?x - t ...) body)`` and its body."""
    variables = node.items[1] if len(node.items) > 1 else None
    inner = dict(scope)
    if isinstance(variables, Group):
        _, declared = parameters(ctx, variables.items, node.span, "variable")
        inner.update(declared)
    else:
        ctx.error(node.span, f"({node.key} (?x - type ...) formula): the variables are missing", "bad-formula")
    if len(node.items) != 3:
        ctx.error(node.span, f"({node.key} (?x - type ...) formula) takes one formula", "bad-formula")
    return inner, node.items[2] if len(node.items) > 2 else None


def _operands(ctx: Context, node: Group, count: int | None) -> list[Token | Group]:
    operands = node.items[1:]
    if count is not None and len(operands) != count:
        noun = "formula" if count == 1 else "formulas"
        ctx.error(node.span, f"({node.key} ...) takes {count} {noun}, {len(operands)} given", "bad-formula")
    return operands


def goal(ctx: Context, node: Token | Group, scope: Scope, role: str) -> None:
    """A goal description: a precondition, a goal, or a formula inside a constraint."""
    if isinstance(node, Token):
        ctx.error(node.span, f"expected a formula such as (predicate ...) here, found '{node.text}'", "bad-formula")
        return
    key = node.key
    if not node.items:
        return  # () is the empty conjunction, true
    if key == "and":
        for item in node.items[1:]:
            goal(ctx, item, scope, role)
    elif key in ("or", "imply"):
        ctx.use(":disjunctive-preconditions", node.head.span)  # type: ignore[union-attr]
        for item in _operands(ctx, node, 2 if key == "imply" else None):
            goal(ctx, item, scope, role)
    elif key == "not":
        ctx.use(":negative-preconditions", node.head.span)  # type: ignore[union-attr]
        for item in _operands(ctx, node, 1):
            goal(ctx, item, scope, role)
    elif key in ("exists", "forall"):
        requirement = ":existential-preconditions" if key == "exists" else ":universal-preconditions"
        ctx.use(requirement, node.head.span)  # type: ignore[union-attr]
        inner, body = _quantified(ctx, node, scope)
        if body is not None:
            goal(ctx, body, inner, role)
    elif key == "preference":
        ctx.use(":preferences", node.head.span)  # type: ignore[union-attr]
        operands = node.items[1:]
        if operands and isinstance(operands[0], Token):
            operands = operands[1:]
        for item in operands:
            goal(ctx, item, scope, role)
    elif key == "=":
        ctx.use(":equality", node.head.span)  # type: ignore[union-attr]
        for item in _operands(ctx, node, 2):
            term(ctx, item, scope, None)
    elif key in COMPARISONS:
        ctx.use(":numeric-fluents", node.head.span)  # type: ignore[union-attr]
        for item in _operands(ctx, node, 2):
            numeric(ctx, item, scope)
    else:
        atom(ctx, node, scope, GOAL_OPERATORS, role)


def atom(ctx: Context, node: Group, scope: Scope, operators: tuple[str, ...], role: str) -> None:
    """``(predicate term ...)``: the predicate declared, the arity and the argument types right."""
    head = node.head
    if head is None:
        ctx.error(node.open.span, "expected a predicate or operator name after '('", "bad-formula")
        return
    declaration = ctx.index.find("predicate", head.key)
    ctx.index.refer("predicate", head.text, head.span, declaration)
    if declaration is None:
        _unknown_head(ctx, node, head, operators, role, scope)
        for item in node.items[1:]:  # names as terms, lists as formulas (the head may be a mistyped 'and')
            if isinstance(item, Token):
                term(ctx, item, scope, None)
            elif role == "effect":
                effect(ctx, item, scope)
            else:
                goal(ctx, item, scope, role)
        return
    _arguments(ctx, node, declaration, scope)


def _arguments(ctx: Context, node: Group, declaration: Declaration, scope: Scope) -> None:
    """The arguments of a predicate's or function's ``node``: as many as declared, of the declared types."""
    arguments = node.items[1:]
    if len(arguments) != len(declaration.parameters):
        count = len(declaration.parameters)
        ctx.error(
            node.span,
            f"'{declaration.name}' takes {count} argument{'s' if count != 1 else ''}, "
            f"{len(arguments)} given: {declaration.signature}",
            "arity",
        )
    for position, item in enumerate(arguments):
        allowed = declaration.parameters[position].types if position < len(declaration.parameters) else None
        term(ctx, item, scope, allowed, (declaration.name, position + 1))


def _unknown_head(ctx: Context, node: Group, head: Token, operators: tuple[str, ...], role: str, scope: Scope) -> None:
    if head.key in NOT_PDDL:
        ctx.error(head.span, NOT_PDDL[head.key], "not-pddl", "sometime-before")
        return
    second = node.items[1] if len(node.items) > 1 else None
    if head.key in PDDL3_OPERATORS and (head.key != "at" or (isinstance(second, Token) and second.key == "end")):
        if role == "constraint":
            message = f"'{head.text}' inside a constraint's formula: PDDL 3 constraints do not nest"
        else:
            message = (
                f"'{head.text}' is a PDDL 3 constraint: it belongs in the problem's (:constraints ...), not in a {role}"
            )
        ctx.error(head.span, message, "misplaced-constraint")
        return
    predicates = ctx.index.names("predicate")
    near_predicate = ctx.closest(head.text, predicates)
    near_operator = ctx.closest(head.text, [o for o in operators if o[0].isalpha()])
    if near_operator is not None and near_predicate is None:
        ctx.unknown(head, f"unknown operator '{head.text}'", operators, "unknown-operator")
        return
    fixes = _declare_predicate(ctx, node, scope)
    ctx.unknown(head, f"unknown predicate '{head.text}'", predicates, "unknown-predicate", fixes)


def _declare_predicate(ctx: Context, node: Group, scope: Scope) -> list[Fix]:
    """The quick fix that adds ``(name ?a - t ...)`` to the domain's (:predicates ...), types guessed
    from the arguments."""
    section = ctx.predicates_section
    head = node.head
    if head is None:
        return []
    after = ctx.insertion_point(":predicates")
    if (section is None or section.close is None) and after is None:
        return []
    arguments = []
    for position, item in enumerate(node.items[1:]):
        kind = "object"
        if isinstance(item, Token):
            found = scope.get(item.key) or ctx.index.find("object", item.key) or ctx.index.find("constant", item.key)
            if found is not None and found.types:
                kind = found.types[0]
        arguments.append(
            f" ?{chr(ord('a') + position % 26)} - {kind}"
            if ":typing" in ctx.used
            else f" ?{chr(ord('a') + position % 26)}"
        )
    title = f"declare predicate '{head.text}'"
    text = f"\n    ({head.text}{''.join(arguments)})"
    if section is not None and section.close is not None:
        at = section.close.span
        return [Fix(title, Span(at.file, at.line, at.column, at.line, at.column), text)]
    assert after is not None
    return [Fix(title, after, f"\n  (:predicates{text})")]


def term(
    ctx: Context,
    item: Token | Group,
    scope: Scope,
    allowed: tuple[str, ...] | None,
    argument: tuple[str, int] | None = None,
) -> None:
    """A variable, constant or object; its type checked against ``allowed`` where known."""
    if isinstance(item, Group):
        numeric(ctx, item, scope)
        return
    if item.text.startswith("?"):
        declaration = scope.get(item.key)
        ctx.index.refer("parameter" if declaration is None else declaration.kind, item.text, item.span, declaration)
        if declaration is None:
            visible = [d.name for d in scope.values()]
            message = f"undefined parameter '{item.text}'"
            if len(visible) == 1:  # the one variable there is: what else could be meant
                fix = Fix(f"change to '{visible[0]}'", item.span, visible[0])
                ctx.error(item.span, message, "undefined-variable", visible[0], [fix])
            else:
                ctx.unknown(item, message, visible, "undefined-variable")
            return
    else:
        declaration = ctx.index.find("constant", item.key)
        kind = "constant"
        if declaration is None and ctx.in_problem:
            declaration, kind = ctx.index.find("object", item.key), "object"
        ctx.index.refer(kind, item.text, item.span, declaration)
        if declaration is None:
            if _is_number(item.text):
                return
            names = ctx.term_names()
            what = "object or constant" if ctx.in_problem else "constant"
            ctx.unknown(item, f"unknown {what} '{item.text}'", names, f"unknown-{kind}")
            return
    if allowed is None or argument is None or not declaration.types:
        return
    if not ctx.is_subtype(declaration.types, allowed):
        have = " or ".join(declaration.types)
        want = " or ".join(allowed)
        ctx.error(
            item.span,
            f"'{item.text}' is of type {have}, but argument {argument[1]} of '{argument[0]}' is of type {want}",
            "argument-type",
        )


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _timed_literal(item: Group) -> bool:
    """Whether ``item`` is ``(at NUMBER literal)``, a timed initial literal (not the predicate ``at``)."""
    return (
        item.key == "at"
        and len(item.items) == 3
        and isinstance(item.items[1], Token)
        and _is_number(item.items[1].text)
        and isinstance(item.items[2], Group)
    )


def numeric(ctx: Context, node: Token | Group, scope: Scope) -> None:
    """A numeric expression: a number, ``(total-cost)``, a function term, arithmetic, ``(is-violated p)``."""
    if isinstance(node, Token):
        if not _is_number(node.text) and not node.text.startswith("?") and node.key != "total-time":
            ctx.error(node.span, f"expected a number or a numeric expression, found '{node.text}'", "bad-number")
        return
    head = node.head
    if head is None:
        ctx.error(node.open.span, "expected a function or an arithmetic operator after '('", "bad-number")
        return
    if head.key in ARITHMETIC:
        for item in node.items[1:]:
            numeric(ctx, item, scope)
        return
    if head.key in ("is-violated", "total-time"):
        return
    declaration = ctx.index.find("function", head.key)
    ctx.index.refer("function", head.text, head.span, declaration)
    if declaration is None:
        ctx.unknown(head, f"unknown function '{head.text}'", ctx.index.names("function"), "unknown-function")
        return
    _arguments(ctx, node, declaration, scope)


def effect(ctx: Context, node: Token | Group, scope: Scope) -> None:
    if isinstance(node, Token):
        ctx.error(node.span, f"expected an effect such as (predicate ...) here, found '{node.text}'", "bad-effect")
        return
    key = node.key
    if not node.items:
        return
    if key == "and":
        for item in node.items[1:]:
            effect(ctx, item, scope)
    elif key == "not":
        for item in _operands(ctx, node, 1):
            if isinstance(item, Group) and item.key in EFFECT_OPERATORS:
                ctx.error(item.span, "(not ...) in an effect takes an atom such as (far ?b)", "bad-effect")
            elif isinstance(item, Group):
                atom(ctx, item, scope, EFFECT_OPERATORS, "effect")
            else:
                effect(ctx, item, scope)
    elif key == "forall":
        ctx.use(":conditional-effects", node.head.span)  # type: ignore[union-attr]
        inner, body = _quantified(ctx, node, scope)
        if body is not None:
            effect(ctx, body, inner)
    elif key == "when":
        ctx.use(":conditional-effects", node.head.span)  # type: ignore[union-attr]
        operands = _operands(ctx, node, 2)
        if len(operands) == 2:
            goal(ctx, operands[0], scope, "condition")
            effect(ctx, operands[1], scope)
    elif key in NUMERIC_EFFECTS:
        operands = _operands(ctx, node, 2)
        if operands and isinstance(operands[0], Group) and operands[0].key == "total-cost":
            ctx.use(":action-costs", node.head.span)  # type: ignore[union-attr]
        for item in operands:
            numeric(ctx, item, scope)
    else:
        atom(ctx, node, scope, EFFECT_OPERATORS, "effect")


def init(ctx: Context, section: Group) -> None:
    """``(:init atom ...)``: ground atoms and ``(= (function ...) number)``."""
    for item in section.items[1:]:
        if isinstance(item, Token):
            ctx.error(item.span, f"(:init ...) lists atoms such as (far green); found '{item.text}'", "bad-init")
        elif item.key == "=":
            ctx.use(":action-costs" if _total_cost(item) else ":numeric-fluents", item.open.span)
            for operand in _operands(ctx, item, 2):
                numeric(ctx, operand, {})
        elif _timed_literal(item):  # (at 10 (road a b)): true from time 10 on
            ctx.use(":timed-initial-literals", item.open.span)
            init(ctx, Group(item.open, item.close, [item.items[0], item.items[2]]))
        elif item.key == "not":
            ctx.warning(
                item.span,
                "(not ...) in (:init ...) says nothing: the initial state lists the true atoms; remove it",
                "negative-init",
            )
        else:
            atom(ctx, item, {}, (), "init")


def _total_cost(node: Group) -> bool:
    first = node.items[1] if len(node.items) > 1 else None
    return isinstance(first, Group) and first.key == "total-cost"


def constraint(ctx: Context, node: Token | Group, scope: Scope) -> None:
    """A PDDL 3.0 constraint: (and ...), (forall (...) ...), (preference ...) or a trajectory operator."""
    if isinstance(node, Token):
        ctx.error(node.span, f"expected a constraint such as (always ...) here, found '{node.text}'", "bad-constraint")
        return
    head = node.head
    if head is None:
        if node.items:
            ctx.error(node.open.span, "expected a PDDL 3 operator after '('", "bad-constraint")
        return
    ctx.use(":constraints", head.span)
    key = head.key
    if key == "and":
        for item in node.items[1:]:
            constraint(ctx, item, scope)
        return
    if key == "forall":
        inner, body = _quantified(ctx, node, scope)
        if body is not None:
            constraint(ctx, body, inner)
        return
    if key == "preference":
        ctx.use(":preferences", head.span)
        operands = node.items[1:]
        if operands and isinstance(operands[0], Token):
            operands = operands[1:]
        for item in operands:
            constraint(ctx, item, scope)
        return
    if key not in PDDL3_OPERATORS:
        if key in NOT_PDDL:
            ctx.error(
                head.span,
                NOT_PDDL[key],
                "not-pddl",
                "sometime-before",
                [Fix("change to 'sometime-before'", head.span, "sometime-before")],
            )
        elif ctx.index.find("predicate", key) is not None:
            ctx.error(
                node.span,
                f"({head.text} ...) is a formula, not a constraint: wrap it in a PDDL 3 operator "
                "such as (always ...) or (sometime ...)",
                "not-a-constraint",
            )
        else:
            operators = (*PDDL3_NAMES, "and", "forall", "preference")
            ctx.unknown(head, f"unknown PDDL 3 operator '{head.text}'", operators, "unknown-operator")
        return
    numbers, formulas = PDDL3_OPERATORS[key]
    operands = node.items[1:]
    if key == "at":
        first = operands[0] if operands else None
        if not isinstance(first, Token) or first.key != "end":
            ctx.error(node.span, "(at end φ) is the only 'at' constraint", "bad-constraint")
            return
        operands = operands[1:]
    elif key in TIMED_OPERATORS and ctx.in_problem:
        ctx.error(
            head.span,
            f"({head.text} ...) is not supported (timed constraints need a temporal planner); "
            "vslsp plans with always, sometime, at-most-once, sometime-before, sometime-after and at end",
            "unsupported",
        )
    for item in operands[: len(numbers)]:
        if not isinstance(item, Token) or not _is_number(item.text):
            ctx.error(item.span, f"({head.text} ...) takes a number here", "bad-constraint")
    formulas_given = operands[len(numbers) :]
    name = "at end" if key == "at" else head.text
    if len(formulas_given) != formulas:
        ctx.error(
            node.span,
            f"({name} ...) takes {formulas} formula{'s' if formulas != 1 else ''}"
            f"{' after its numbers' if numbers else ''}, {len(formulas_given)} given",
            "bad-constraint",
        )
    for item in formulas_given:
        goal(ctx, item, scope, "constraint")
