"""The declaration index of the PDDL language engine: every declared name with its place and the
comment above it, and every reference to it, across a domain and its problem.

A language server answers hover (:attr:`Declaration.signature`, :attr:`Declaration.comment`), go to
definition (:meth:`Index.symbol_at` then :attr:`Reference.declaration`), find references and rename
(:meth:`Index.references_to`), completion (:meth:`Index.names`) and the outline
(:meth:`Index.in_file`) from it alone.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field

from vslsp.symbolic.language.diagnostics import Span

#: The kinds of declaration, in the order an outline lists them.
KINDS = (
    "domain",
    "problem",
    "requirement",
    "type",
    "constant",
    "predicate",
    "function",
    "action",
    "object",
    "parameter",
    "variable",
)


@dataclass(frozen=True, slots=True)
class Parameter:
    """A typed variable of a predicate, function or action: ``?b - block`` is ``Parameter("?b", ("block",))``
    (``(either a b)`` gives two types; untyped is ``("object",)``)."""

    name: str
    types: tuple[str, ...]
    span: Span

    def to_pddl(self) -> str:
        kind = self.types[0] if len(self.types) == 1 else f"(either {' '.join(self.types)})"
        return f"{self.name} - {kind}"


@dataclass(frozen=True, slots=True, eq=False)
class Declaration:
    """One declared name.

    ``kind``: one of :data:`KINDS`. ``name`` as written; ``span`` the name's token; ``extent`` the whole
    declaration (the ``(:action ...)`` list; for a type, object or constant: the name); ``comment``: the
    comment lines just above the declaration (or at the end of its line). ``parameters``: a predicate's,
    function's or action's parameters. ``types``: an object's, constant's, parameter's or variable's
    type(s), a type's parent(s) (``()`` for a type with no declared parent). ``scope``: where a parameter
    or quantified variable is visible.
    """

    kind: str
    name: str
    span: Span
    extent: Span
    comment: str = ""
    parameters: tuple[Parameter, ...] = ()
    types: tuple[str, ...] = ()
    scope: Span | None = None

    @property
    def key(self) -> str:
        return self.name.lower()

    @property
    def signature(self) -> str:
        """What a hover shows: ``(far ?b - block)``, ``(:action push :parameters (?b - block))``,
        ``green - block``, ``type area - surface``."""
        params = " ".join(p.to_pddl() for p in self.parameters)
        if self.kind in ("predicate", "function"):
            return f"({self.name}{' ' + params if params else ''})"
        if self.kind == "action":
            return f"(:action {self.name} :parameters ({params}))"
        if self.kind == "type":
            return f"type {self.name}" + (f" - {' '.join(self.types)}" if self.types else "")
        if self.types:
            kind = self.types[0] if len(self.types) == 1 else f"(either {' '.join(self.types)})"
            return f"{self.name} - {kind}"
        return f"{self.kind} {self.name}"


@dataclass(frozen=True, slots=True, eq=False)
class Reference:
    """A use of a name: ``kind`` as in :data:`KINDS` (what the name is taken to be), its token's ``span``,
    and the ``declaration`` it resolves to (None for an unknown name, which has a diagnostic)."""

    kind: str
    name: str
    span: Span
    declaration: Declaration | None


@dataclass(slots=True)
class Index:
    """Declarations and references of one analysis (a domain and, optionally, its problem)."""

    declarations: list[Declaration] = field(default_factory=list)
    references: list[Reference] = field(default_factory=list)
    _by_kind: dict[str, dict[str, Declaration]] = field(default_factory=dict)
    # built on first use, forgotten on each change: what a server asks once per keystroke or hover
    _by_line: dict[tuple[str, int], list[Declaration | Reference]] | None = None
    _uses: dict[int, list[Reference]] | None = None
    _names: dict[str, list[str]] = field(default_factory=dict)

    def declare(self, declaration: Declaration) -> Declaration | None:
        """Add ``declaration``; the earlier one of the same kind and name if there is one (then the first
        stays the one names resolve to). Parameters and variables are not looked up by name here."""
        self.declarations.append(declaration)
        self._by_line = None
        self._names.pop(declaration.kind, None)
        if declaration.kind in ("parameter", "variable"):
            return None
        table = self._by_kind.setdefault(declaration.kind, {})
        earlier = table.get(declaration.key)
        if earlier is None:
            table[declaration.key] = declaration
        return earlier

    def refer(self, kind: str, name: str, span: Span, declaration: Declaration | None) -> Reference:
        reference = Reference(kind, name, span, declaration)
        self.references.append(reference)
        self._by_line = self._uses = None
        return reference

    def find(self, kind: str, name: str) -> Declaration | None:
        """The declaration of ``kind`` named ``name`` (case ignored), or None."""
        table = self._by_kind.get(kind)
        return table.get(name.lower()) if table is not None else None

    def names(self, kind: str) -> list[str]:
        """The declared names of ``kind`` as written, in declaration order (for completion); one list
        per kind until the next declaration of that kind (a check asks for them once per unknown name),
        not to be changed by the caller."""
        names = self._names.get(kind)
        if names is None:
            names = self._names[kind] = [d.name for d in self._by_kind.get(kind, {}).values()]
        return names

    def of_kind(self, kind: str) -> list[Declaration]:
        return list(self._by_kind.get(kind, {}).values())

    def in_file(self, file: str) -> list[Declaration]:
        """The declarations written in ``file``, in the order written (the outline)."""
        return sorted((d for d in self.declarations if d.span.file == file), key=lambda d: (d.span.line, d.span.column))

    def symbol_at(self, file: str, line: int, column: int) -> Declaration | Reference | None:
        """The declaration or reference whose name covers (``line``, ``column``) (1-based), or None."""
        if self._by_line is None:
            self._by_line = {}
            for item in self._all():
                self._by_line.setdefault((item.span.file, item.span.line), []).append(item)
        for item in self._by_line.get((file, line), ()):
            if item.span.column <= column <= item.span.end_column:
                return item
        return None

    def references_to(self, declaration: Declaration) -> list[Reference]:
        """Every reference that resolves to ``declaration`` (the declaration itself not included)."""
        if self._uses is None:
            self._uses = {}
            for reference in self.references:
                if reference.declaration is not None:
                    self._uses.setdefault(id(reference.declaration), []).append(reference)
        return list(self._uses.get(id(declaration), ()))

    def _all(self) -> Iterator[Declaration | Reference]:
        yield from self.declarations
        yield from self.references
