"""Reading the declarations of a domain and a problem into the index: requirements, types (with
their parents), constants, predicates, functions, actions with their parameters, objects.

Formulas (preconditions, effects, the initial state, goals, constraints) are checked afterwards by
:mod:`vslsp.symbolic.language.formulas`, once every name they may use is declared.
"""

from __future__ import annotations

from dataclasses import dataclass

from vslsp.symbolic.budget import MAX_TYPE_DEPTH, type_depths
from vslsp.symbolic.language.context import Context
from vslsp.symbolic.language.diagnostics import Fix, Span
from vslsp.symbolic.language.index import Declaration, Parameter
from vslsp.symbolic.language.syntax import Document, Group, Token
from vslsp.symbolic.language.vocabulary import (
    ACTION_KEYWORDS,
    DOMAIN_SECTIONS,
    IMPLIED,
    PROBLEM_SECTIONS,
    REQUIREMENTS,
)


@dataclass(eq=False)
class TypeSpec:
    """The type after ``-`` shared by the names before it: its tokens (several for ``either``), the
    ``either`` list if any, and once resolved, the lower-case names."""

    tokens: list[Token]
    either: Group | None = None
    resolved: tuple[str, ...] | None = None


_UNTYPED = TypeSpec([])


@dataclass
class Typed:
    """One entry of a typed list: ``name`` and its type (``spec.tokens`` empty: object)."""

    name: Token | Group
    spec: TypeSpec = _UNTYPED

    @property
    def types(self) -> list[Token]:
        return self.spec.tokens

    @property
    def either(self) -> Group | None:
        return self.spec.either


@dataclass
class Body:
    """A formula to check once all names are declared: ``role`` is precondition, effect, goal, init,
    constraints or metric; ``scope`` the variables visible in it."""

    role: str
    node: Token | Group
    scope: dict[str, Declaration]
    owner: Group


def typed_list(ctx: Context, items: list[Token | Group]) -> list[Typed]:
    """The entries of ``a b - t c - (either u v) d``; ``-`` notes that :typing is used."""
    entries: list[Typed] = []
    pending: list[Typed] = []
    index = 0
    while index < len(items):
        item = items[index]
        if isinstance(item, Token) and item.text == "-":
            ctx.use(":typing", item.span)
            kind = items[index + 1] if index + 1 < len(items) else None
            if kind is None:
                ctx.error(item.span, "'-' must be followed by a type", "missing-type")
            elif not pending:
                ctx.error(item.span, "'-' with no name before it", "missing-name")
            if isinstance(kind, Token):
                spec = TypeSpec([kind])
                for entry in pending:
                    entry.spec = spec
            elif isinstance(kind, Group):
                names = [t for t in kind.items[1:] if isinstance(t, Token)]
                if kind.key != "either" or not names:
                    ctx.error(kind.span, "a type is a name or (either TYPE ...)", "bad-type")
                spec = TypeSpec(names, kind)
                for entry in pending:
                    entry.spec = spec
            entries.extend(pending)
            pending = []
            index += 2
            continue
        pending.append(Typed(item))
        index += 1
    entries.extend(pending)
    return entries


def resolve_types(ctx: Context, entry: Typed, either_allowed: bool, numeric: bool = False) -> tuple[str, ...]:
    """The lower-case types of ``entry`` (``("object",)`` when untyped), each type written a reference
    (once for all the names that share it)."""
    spec = entry.spec
    if spec.resolved is not None:
        return spec.resolved
    if spec.either is not None and not either_allowed:
        head = spec.either.head or spec.either.open
        ctx.error(head.span, "(either ...) types are supported only in a predicate's parameters", "unsupported")
    spec.resolved = tuple(ctx.type_reference(t, numeric) for t in spec.tokens) if spec.tokens else ("object",)
    return spec.resolved


def parameters(
    ctx: Context, items: list[Token | Group], scope: Span | None, kind: str | None, either_allowed: bool = False
) -> tuple[tuple[Parameter, ...], dict[str, Declaration]]:
    """The parameters of a predicate or action, or a quantifier's variables; declared as ``kind``
    (parameter or variable, None: not declared) visible in ``scope``."""
    found: list[Parameter] = []
    visible: dict[str, Declaration] = {}
    for entry in typed_list(ctx, items):
        name = entry.name
        types = resolve_types(ctx, entry, either_allowed)
        if not isinstance(name, Token) or not name.text.startswith("?"):
            span = name.span
            ctx.error(span, "a parameter is a variable such as '?x'", "bad-parameter")
            continue
        if name.key in visible:
            ctx.error(name.span, f"parameter '{name.text}' is declared twice", "duplicate")
            continue
        found.append(Parameter(name.text, types, name.span))
        declaration = Declaration(kind or "parameter", name.text, name.span, name.span, types=types, scope=scope)
        visible[name.key] = declaration
        if kind is not None:
            ctx.index.declare(declaration)
    return tuple(found), visible


def define_header(ctx: Context, document: Document) -> tuple[Group | None, str, Token | None]:
    """The ``(define (domain|problem NAME) ...)`` of ``document``: the define list, its kind, its name."""
    groups = document.groups
    if not groups:
        if not document.diagnostics:
            span = Span(document.file, 1, 1, 1, 1)
            ctx.error(span, "the file is empty; expected (define (domain ...)) or (define (problem ...))", "empty")
        return None, "", None
    for extra in groups[1:]:
        ctx.error(extra.open.span, "a file holds one (define ...); this list is after its end", "outside-define")
    define = groups[0]
    if define.key != "define":
        ctx.error(
            (define.head or define.open).span,
            "a PDDL file starts with (define (domain NAME) ...) or (define (problem NAME) ...)",
            "no-define",
        )
        return None, "", None
    kind_group = define.items[1] if len(define.items) > 1 else None
    if not isinstance(kind_group, Group) or kind_group.key not in ("domain", "problem"):
        span = kind_group.span if kind_group is not None else define.open.span
        ctx.error(span, "expected (domain NAME) or (problem NAME) after 'define'", "no-name")
        return define, "", None
    name = kind_group.items[1] if len(kind_group.items) > 1 else None
    if not isinstance(name, Token):
        ctx.error(kind_group.span, f"the {kind_group.key} needs a name: ({kind_group.key} NAME)", "no-name")
        return define, kind_group.key, None
    return define, kind_group.key, name


#: The sections of PDDL+ (Fox and Long 2006), which no planner of vslsp's takes.
PDDL_PLUS = {":process": "processes", ":event": "events"}


def sections(ctx: Context, define: Group, allowed: tuple[str, ...], kind: str) -> list[Group]:
    """The sections of a define list, each a ``(:keyword ...)`` list of ``allowed``; others reported."""
    found: list[Group] = []
    other = PROBLEM_SECTIONS if kind == "domain" else DOMAIN_SECTIONS
    for item in define.items[2:]:
        if not isinstance(item, Group) or not item.key.startswith(":"):
            ctx.error(item.span, f"expected a section such as {allowed[0]} here", "not-a-section")
            continue
        head = item.head
        assert head is not None
        if item.key in allowed:
            found.append(item)
        elif item.key in other:
            ctx.error(
                head.span,
                f"'{head.text}' belongs in a {'problem' if kind == 'domain' else 'domain'} file",
                "misplaced-section",
            )
        elif item.key in PDDL_PLUS:
            ctx.error(
                head.span,
                f"PDDL+ {PDDL_PLUS[item.key]} ({head.text} ...) are not supported; vslsp reads PDDL 2.1/2.2: "
                "numeric fluents, durative actions and timed initial literals",
                "unsupported",
            )
        else:
            ctx.unknown(head, f"unknown section '{head.text}'", allowed, "unknown-section")
    return found


def requirements(ctx: Context, section: Group, document: Document) -> None:
    for item in section.items[1:]:
        if not isinstance(item, Token):
            ctx.error(item.span, "requirements are keywords such as :typing", "bad-requirement")
            continue
        if item.key not in REQUIREMENTS:
            ctx.unknown(item, f"unknown requirement '{item.text}'", REQUIREMENTS, "unknown-requirement")
            continue
        ctx.index.declare(Declaration("requirement", item.text, item.span, item.span))
        pending = [item.key]
        while pending:
            word = pending.pop()
            if word not in ctx.declared_requirements:
                ctx.declared_requirements.add(word)
                pending.extend(IMPLIED.get(word, ()))


def types(ctx: Context, section: Group, document: Document) -> None:
    """Declare the types of ``(:types ...)``; a parent never declared as a type is a warning (and then
    declared there), a type declared twice a warning (the last parent counts), a cycle an error."""
    ctx.types_section = section
    entries = typed_list(ctx, section.items[1:])
    for entry in entries:
        name = entry.name
        if not isinstance(name, Token):
            ctx.error(name.span, "a type is a name", "bad-type")
            continue
        if name.key == "object":
            continue
        comment = document.comment_above(name.line)
        declaration = Declaration(
            "type", name.text, name.span, name.span, comment, types=tuple(t.key for t in entry.types)
        )
        ctx.reserved(declaration, "type")
        earlier = ctx.index.declare(declaration)
        if earlier is not None:
            ctx.warning(
                name.span,
                f"type '{name.text}' is declared twice (first at line {earlier.span.line}); its last parent counts",
                "duplicate-type",
            )
        ctx.parents[name.key] = tuple(t.key for t in entry.types) or ("object",)
    specs = list({id(entry.spec): entry.spec for entry in entries}.values())
    for spec in specs:
        if spec.either is not None:
            ctx.error(spec.either.span, "a type's parent is one type, not (either ...)", "bad-type")
        for parent in spec.tokens:
            found = ctx.index.find("type", parent.key)
            if found is None and parent.key != "object":
                message = f"type '{parent.text}' is used as a parent but not declared; declare it in (:types ...)"
                at = section.close.span if section.close else parent.span
                fix = Fix(
                    f"declare type '{parent.text}'",
                    Span(at.file, at.line, at.column, at.line, at.column),
                    f" {parent.text}",
                )
                suggestion = ctx.closest(parent.text, ctx.index.names("type"))
                ctx.warning(parent.span, message, "undeclared-parent", suggestion, [fix])
                found = Declaration("type", parent.text, parent.span, parent.span)
                ctx.index.declare(found)
                ctx.parents.setdefault(parent.key, ("object",))
            ctx.index.refer("type", parent.text, parent.span, found)
    ctx.types_declared()
    _type_cycles(ctx)
    _type_depth(ctx)


def _type_cycles(ctx: Context) -> None:
    """An error at the first type written of each cycle of first parents, in time linear in the types."""
    following = {child: next((p for p in parents if p != "object"), None) for child, parents in ctx.parents.items()}
    order = {child: index for index, child in enumerate(ctx.parents)}
    walk_of: dict[str, int] = {}
    for walk, start in enumerate(ctx.parents):
        current: str | None = start
        path: list[str] = []
        while current is not None and current not in walk_of:
            walk_of[current] = walk
            path.append(current)
            current = following.get(current)
        if current is None or walk_of[current] != walk:
            continue  # ends at object, or runs into a walk seen before
        cycle = path[path.index(current) :]
        first = min(range(len(cycle)), key=lambda i: order.get(cycle[i], len(order)))
        cycle = cycle[first:] + cycle[:first]
        declaration = ctx.index.find("type", cycle[0])
        if declaration is not None:
            ctx.error(
                declaration.span,
                f"the types form a cycle ({' - '.join([*cycle, cycle[0]])}); a type cannot be its own ancestor",
                "type-cycle",
            )


def _type_depth(ctx: Context) -> None:
    """An error at the first type written whose chain of parents is longer than :data:`MAX_TYPE_DEPTH`."""
    depths = type_depths(ctx.parents)
    deepest = max(depths.values(), default=0)
    if deepest <= MAX_TYPE_DEPTH:
        return
    ctx.types_too_deep = True
    over = next(t for t in ctx.parents if depths.get(t, 0) > MAX_TYPE_DEPTH)
    declaration = ctx.index.find("type", over)
    if declaration is not None:
        ctx.error(
            declaration.span,
            f"the type hierarchy is {deepest} types deep: nested too deeply (limit {MAX_TYPE_DEPTH}); "
            "give the types fewer levels of parents",
            "types-too-deep",
        )


def constants(ctx: Context, section: Group, document: Document, kind: str, with_types: bool = True) -> None:
    """Declare the constants of a domain or the objects of a problem (``kind``: constant or object);
    ``with_types`` False (a problem without its domain): the types are taken as written, unchecked."""
    for entry in typed_list(ctx, section.items[1:]):
        name = entry.name
        if with_types:
            found = resolve_types(ctx, entry, either_allowed=False)
        else:
            found = tuple(t.key for t in entry.types) or ("object",)
        if not isinstance(name, Token) or name.text.startswith("?"):
            ctx.error(
                name.span,
                f"an {kind} is a name such as 'green'" if kind == "object" else f"a {kind} is a name such as 'green'",
                f"bad-{kind}",
            )
            continue
        comment = document.comment_above(name.line)
        declaration = Declaration(kind, name.text, name.span, name.span, comment, types=found)
        if kind == "object" and ctx.index.find("constant", name.key) is not None:
            ctx.warning(name.span, f"'{name.text}' is a constant of the domain already", "object-is-constant")
        ctx.declare(declaration, kind)


def predicates(ctx: Context, section: Group, document: Document, kind: str = "predicate") -> None:
    """Declare the predicates of ``(:predicates ...)`` (or the functions of ``(:functions ...)``)."""
    if kind == "predicate":
        ctx.predicates_section = section
    items = section.items[1:]
    index = 0
    while index < len(items):
        item = items[index]
        index += 1
        if isinstance(item, Token) and item.text == "-" and kind == "function" and index < len(items):
            value = items[index]
            if isinstance(value, Token) and value.key != "number":
                ctx.type_reference(value, numeric=True)
            index += 1
            continue
        if not isinstance(item, Group) or item.head is None:
            ctx.error(item.span, f"expected a {kind} such as (name ?x - type)", f"bad-{kind}")
            continue
        head = item.head
        params, _ = parameters(ctx, item.items[1:], None, None, either_allowed=True)
        comment = document.comment_above(item.open.line)
        ctx.declare(Declaration(kind, head.text, head.span, item.span, comment, params), kind)
        if kind == "function":
            if head.key == "total-cost" and not params:
                ctx.use(":action-costs", head.span)
            else:
                ctx.use(":numeric-fluents", head.span)  # planned by vslsp.symbolic.engines.pddl21


def action(
    ctx: Context,
    section: Group,
    document: Document,
    keywords: tuple[str, ...] = ACTION_KEYWORDS,
    roles: tuple[tuple[str, str], ...] = (("precondition", ":precondition"), ("effect", ":effect")),
) -> list[Body]:
    """Declare an ``(:action NAME :parameters (...) ...)``; its precondition and effect to check later.
    A durative action passes its ``keywords`` and the ``roles`` of its bodies (``(role, keyword)``)."""
    name = section.items[1] if len(section.items) > 1 else None
    if not isinstance(name, Token) or name.key.startswith(":"):
        ctx.error(section.span if name is None else name.span, "(:action NAME ...) needs a name", "no-name")
        return []
    bodies: list[Body] = []
    params: tuple[Parameter, ...] = ()
    scope: dict[str, Declaration] = {}
    values: dict[str, Token | Group] = {}
    items = section.items[2:]
    index = 0
    while index < len(items):
        keyword = items[index]
        value = items[index + 1] if index + 1 < len(items) else None
        index += 2
        if not isinstance(keyword, Token) or not keyword.key.startswith(":"):
            ctx.error(keyword.span, f"expected {', '.join(keywords[:-1])} or {keywords[-1]} here", "bad-action")
            index -= 1
            continue
        if keyword.key not in keywords:
            ctx.unknown(keyword, f"unknown keyword '{keyword.text}' in an action", keywords, "unknown-keyword")
            continue
        if value is None:
            ctx.error(keyword.span, f"'{keyword.text}' needs a value", "bad-action")
            continue
        values[keyword.key] = value
    given = values.get(":parameters")
    if isinstance(given, Group):
        params, scope = parameters(ctx, given.items, section.span, "parameter")
    elif given is not None:
        ctx.error(given.span, ":parameters takes a list such as (?b - block)", "bad-action")
    comment = document.comment_above(section.open.line)
    ctx.declare(Declaration("action", name.text, name.span, section.span, comment, params), "action")
    for role, key in roles:
        if key in values:
            bodies.append(Body(role, values[key], scope, section))
    return bodies
