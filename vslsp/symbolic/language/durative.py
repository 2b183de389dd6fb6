"""Checking durative actions (PDDL 2.1): ``(:durative-action NAME :parameters (...) :duration D
:condition C :effect E)``.

``D`` constrains ``?duration`` (``(= ?duration 4)``, ``(and (>= ?duration 1) (<= ?duration (f ?x)))``);
``C`` is a conjunction of ``(at start φ)``, ``(over all φ)`` and ``(at end φ)`` over goal
descriptions; ``E`` a conjunction of ``(at start e)`` and ``(at end e)`` over effects (``forall``
and ``when`` around them as in PDDL 2.1). Inside the wrappers the formulas are checked as a
precondition and an effect are (:mod:`vslsp.symbolic.language.formulas`).
"""

from __future__ import annotations

from vslsp.symbolic.language.context import Context
from vslsp.symbolic.language.declarations import Body, action
from vslsp.symbolic.language.formulas import Scope, _quantified, effect, goal, numeric
from vslsp.symbolic.language.syntax import Document, Group, Token

DURATIVE_KEYWORDS = (":parameters", ":duration", ":condition", ":effect")
ROLES = (("duration", ":duration"), ("timed-condition", ":condition"), ("timed-effect", ":effect"))
TIMED_ROLES = tuple(role for role, _ in ROLES)
CONDITION_TIMES = ("at start", "over all", "at end")
EFFECT_TIMES = ("at start", "at end")


def durative_action(ctx: Context, section: Group, document: Document) -> list[Body]:
    """Declare a durative action (an ``action`` of the index: outline, hover and rename as any)."""
    head = section.head
    if head is not None:
        ctx.use(":durative-actions", head.span)
    return action(ctx, section, document, DURATIVE_KEYWORDS, ROLES)


def check_timed(ctx: Context, body: Body) -> None:
    if body.role == "duration":
        duration(ctx, body.node, body.scope)
    elif body.role == "timed-condition":
        timed(ctx, body.node, body.scope, CONDITION_TIMES)
    elif body.role == "timed-effect":
        timed(ctx, body.node, body.scope, EFFECT_TIMES)


def _time_of(node: Group) -> str:
    """``at start``, ``over all``, ``at end`` (lower case) when ``node`` is such a wrapper, else ""."""
    words = [i.key for i in node.items[:2] if isinstance(i, Token)]
    return " ".join(words) if len(words) == 2 and " ".join(words) in CONDITION_TIMES else ""


def timed(ctx: Context, node: Token | Group, scope: Scope, times: tuple[str, ...]) -> None:
    """A durative action's condition (``times``: :data:`CONDITION_TIMES`) or effect (:data:`EFFECT_TIMES`)."""
    is_effect = times == EFFECT_TIMES
    what = "effect" if is_effect else "condition"
    if isinstance(node, Token) or not node.items:
        if isinstance(node, Token):
            ctx.error(node.span, f"expected a timed {what} such as (at start ...) here", "bad-timed")
        return
    if node.key == "and":
        for item in node.items[1:]:
            timed(ctx, item, scope, times)
        return
    if is_effect and node.key == "forall":
        inner, inside = _quantified(ctx, node, scope)
        if inside is not None:
            timed(ctx, inside, inner, times)
        return
    when = _time_of(node)
    if when not in times:
        wrappers = ", ".join(f"({t} ...)" for t in times)
        found = f"({when} ...)" if when else f"({node.key or '...'} ...)"
        ctx.error(node.span, f"a durative action's {what} is {wrappers}; found {found}", "bad-timed")
        return
    if len(node.items) != 3:
        ctx.error(node.span, f"({when} ...) takes one {what}", "bad-timed")
        return
    if is_effect:
        effect(ctx, node.items[2], scope)
    else:
        goal(ctx, node.items[2], scope, "precondition")


def duration(ctx: Context, node: Token | Group, scope: Scope) -> None:
    """``(= ?duration N)``, ``(<= ?duration N)``, ``(>= ?duration N)``, a conjunction of them, or ``()``."""
    if isinstance(node, Token) or not node.items:
        if isinstance(node, Token):
            ctx.error(node.span, "expected a duration constraint such as (= ?duration 4)", "bad-duration")
        return
    if node.key == "and":
        for item in node.items[1:]:
            duration(ctx, item, scope)
        return
    operands = node.items[1:]
    first = operands[0] if operands else None
    if (
        node.key not in ("=", "<=", ">=")
        or len(operands) != 2
        or not (isinstance(first, Token) and first.key == "?duration")
    ):
        ctx.error(
            node.span, "a duration constraint is (= ?duration N), (<= ?duration N) or (>= ?duration N)", "bad-duration"
        )
        return
    numeric(ctx, operands[1], scope)
