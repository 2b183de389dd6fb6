"""The state of one analysis shared by the engine's checks: the index being built, the diagnostics,
the type hierarchy, the requirements used, and the helpers that resolve a name or say it is unknown."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field

from vslsp.symbolic.language.diagnostics import ERROR, WARNING, Diagnostic, Fix, Span, SuggestionBudget, closest
from vslsp.symbolic.language.index import Declaration, Index
from vslsp.symbolic.language.syntax import Group, Token
from vslsp.symbolic.language.vocabulary import is_reserved_name, reserved_name_message


@dataclass
class Context:
    """What the checks of one domain (and problem) read and write."""

    index: Index = field(default_factory=Index)
    diagnostics: list[Diagnostic] = field(default_factory=list)
    #: type -> its parent types (the last declaration wins, as in the planner's reader)
    parents: dict[str, tuple[str, ...]] = field(default_factory=dict)
    #: requirement -> the first place that needs it
    used: dict[str, Span] = field(default_factory=dict)
    declared_requirements: set[str] = field(default_factory=set)
    #: the domain's (:predicates ...) and (:types ...) lists, where "declare it" fixes insert
    predicates_section: Group | None = None
    types_section: Group | None = None
    #: where a missing (:types ...) or (:predicates ...) section is inserted: after the header's last
    #: list of (domain NAME), (:requirements ...), (:types ...), (:constants ...)
    header_end: dict[str, Span] = field(default_factory=dict)
    in_problem: bool = False
    #: the type hierarchy is deeper than its limit (reported): argument types are then not compared
    types_too_deep: bool = False
    #: what the did-you-mean suggestions of this analysis may still compare
    suggestions: SuggestionBudget = field(default_factory=SuggestionBudget)
    _term_names: tuple[tuple[bool, int], list[str]] | None = None
    _ancestors: dict[str, list[str]] = field(default_factory=dict)
    _subtype: dict[tuple[tuple[str, ...], tuple[str, ...]], bool] = field(default_factory=dict)

    def error(
        self, span: Span, message: str, code: str, suggestion: str | None = None, fixes: Iterable[Fix] = ()
    ) -> None:
        self.diagnostics.append(Diagnostic(span, ERROR, message, code, suggestion, tuple(fixes)))

    def warning(
        self, span: Span, message: str, code: str, suggestion: str | None = None, fixes: Iterable[Fix] = ()
    ) -> None:
        self.diagnostics.append(Diagnostic(span, WARNING, message, code, suggestion, tuple(fixes)))

    def term_names(self) -> list[str]:
        """The constants, and in a problem the objects too: what a name in a formula may be (one list per
        state of the index, not to be changed)."""
        key = (self.in_problem, len(self.index.declarations))
        if self._term_names is None or self._term_names[0] != key:
            names = self.index.names("constant") + (self.index.names("object") if self.in_problem else [])
            self._term_names = (key, names)
        return self._term_names[1]

    def closest(self, name: str, candidates: Iterable[str]) -> str | None:
        """:func:`~vslsp.symbolic.language.diagnostics.closest` within this analysis's budget of comparisons."""
        return closest(name, candidates, self.suggestions)

    def use(self, requirement: str, span: Span) -> None:
        """Note that the files need ``requirement`` (first at ``span``)."""
        self.used.setdefault(requirement, span)

    def unknown(
        self, token: Token, message: str, candidates: Iterable[str], code: str, fixes: Iterable[Fix] = ()
    ) -> None:
        """An error ``message`` at ``token`` with the closest candidate as suggestion and first fix."""
        suggestion = self.closest(token.text, candidates)
        all_fixes = [Fix(f"change to '{suggestion}'", token.span, suggestion)] if suggestion else []
        all_fixes.extend(fixes)
        self.error(token.span, message, code, suggestion, all_fixes)

    # --- types -------------------------------------------------------------------------------------

    def types_declared(self) -> None:
        """Forget what was derived from the type hierarchy (it has just changed)."""
        self._ancestors.clear()
        self._subtype.clear()

    def type_known(self, name: str) -> bool:
        return name == "object" or self.index.find("type", name) is not None

    def ancestors(self, name: str) -> list[str]:
        """``name`` and its ancestors up to ``object`` (cycles cut); computed once per type, after the
        types are declared."""
        cached = self._ancestors.get(name)
        if cached is not None:
            return cached
        chain = [name]
        seen = {name}
        index = 0
        while index < len(chain):
            for parent in self.parents.get(chain[index], ()):
                if parent not in seen:
                    seen.add(parent)
                    chain.append(parent)
            index += 1
        if "object" not in chain:
            chain.append("object")
        self._ancestors[name] = chain
        return chain

    def is_subtype(self, types: tuple[str, ...], allowed: tuple[str, ...]) -> bool:
        """Whether every type of ``types`` (an either-list) is one of ``allowed`` or below one of them; an
        undefined type (reported where it is written) matches anything."""
        if self.types_too_deep:
            return True
        known = self._subtype.get((types, allowed))
        if known is None:
            known = not all(self.type_known(t) for t in (*types, *allowed)) or all(
                any(a in self.ancestors(t) for a in allowed) for t in types
            )
            self._subtype[(types, allowed)] = known
        return known

    def type_reference(self, token: Token, numeric: bool = False) -> str:
        """Resolve a type name written at ``token`` (a reference, or an "undefined type" error there);
        ``numeric``: where ``number`` is a type too (a function's value)."""
        key = token.key
        declaration = self.index.find("type", key)
        self.index.refer("type", token.text, token.span, declaration)
        if declaration is None and key != "object" and not (numeric and key == "number"):
            candidates = ["object", *self.index.names("type")]
            fixes = self.declare_type_fixes(token.text)
            self.unknown(token, f"undefined type '{token.text}'", candidates, "undefined-type", fixes)
        return key

    def declare_type_fixes(self, name: str) -> list[Fix]:
        """The quick fix that declares type ``name``: in (:types ...), or a new (:types ...) section."""
        title = f"declare type '{name}'"
        section = self.types_section
        if section is not None and section.close is not None:
            at = section.close.span
            return [Fix(title, Span(at.file, at.line, at.column, at.line, at.column), f" {name}")]
        after = self.insertion_point(":types")
        return [Fix(title, after, f"\n  (:types {name})")] if after is not None else []

    def insertion_point(self, section: str) -> Span | None:
        """The empty span just after the header list that a new ``section`` follows, or None."""
        order = (
            ("domain", ":requirements") if section == ":types" else ("domain", ":requirements", ":types", ":constants")
        )
        found = [self.header_end[key] for key in order if key in self.header_end]
        if not found:
            return None
        at = max(found, key=lambda span: (span.end_line, span.end_column))
        return Span(at.file, at.end_line, at.end_column, at.end_line, at.end_column)

    # --- declarations ------------------------------------------------------------------------------

    def declare(self, declaration: Declaration, what: str) -> None:
        """Add ``declaration`` to the index; a second one of the same name is an error at its name, and so
        is a name that is a word of PDDL (``and``, ``forall`` ...)."""
        self.reserved(declaration, what)
        earlier = self.index.declare(declaration)
        if earlier is not None:
            where = f"line {earlier.span.line}" + (
                "" if earlier.span.file == declaration.span.file else f" of {earlier.span.file}"
            )
            self.error(
                declaration.span, f"{what} '{declaration.name}' is declared twice (first at {where})", "duplicate"
            )

    def reserved(self, declaration: Declaration, what: str) -> None:
        """An error at ``declaration`` when its name is a word of PDDL (:data:`RESERVED_NAMES`)."""
        if is_reserved_name(declaration.name):
            self.error(declaration.span, reserved_name_message(declaration.name, what), "reserved-name")
