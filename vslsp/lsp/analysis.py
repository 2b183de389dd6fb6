"""The engine's analysis of an open document, kept while its text (and its domain's) stays the same.

A domain is analysed alone; a problem with the domain it names (:class:`~vslsp.lsp.workspace.Files`
finds it), so that its predicates, types and constants resolve; a problem whose domain is nowhere
gets its syntax checked and a warning at ``(:domain NAME)``. Files are named by path in the engine
(what its messages say) and mapped back to URIs here.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass, field
from pathlib import Path

from vslsp.lsp.positions import UTF16, Lines
from vslsp.lsp.workspace import CHOSEN, DOMAIN, PLAN, PROBLEM, Files, path_of
from vslsp.symbolic.language import (
    ERROR,
    WARNING,
    Analysis,
    Declaration,
    Diagnostic,
    Fix,
    Index,
    Reference,
    Span,
    analyse,
    closest,
)
from vslsp.symbolic.language.plans import analyse_plan

_WORD = re.compile(r"[^\s();]+")
_COMMENT = re.compile(r";[^\n]*")
#: How many analyses are kept (the open documents one is working on, and their domains).
_KEPT = 32
#: The deepest nesting of parentheses analysed. Real domains nest a dozen deep; the engine reads
#: formulas recursively, so a deeper document gets this one error instead of an analysis.
NESTING_LIMIT = 256
_PARENTHESIS = re.compile(r"[()]|;[^\n]*")


@dataclass
class Checked:
    """One document's analysis: ``uri`` the document, ``domain_uri`` the domain read with it (the
    document itself for a domain; None for a problem without its domain), ``analysis`` the engine's
    result, ``extra`` the server's own diagnostics (the missing domain)."""

    uri: str
    kind: str
    domain_uri: str | None
    analysis: Analysis
    texts: dict[str, str]  # uri -> the text analysed
    extra: list[Diagnostic] = field(default_factory=list)
    _uris: dict[str, str] = field(default_factory=dict)  # engine file name -> uri
    encoding: str = UTF16  # the position encoding agreed with the client
    _lines: dict[str, Lines] = field(default_factory=dict)

    @property
    def file(self) -> str:
        """The document's name in the engine's spans."""
        return path_of(self.uri)

    def uri_of(self, file: str) -> str:
        return self._uris.get(file, file)

    def lines(self, uri: str) -> Lines:
        if uri not in self._lines:
            self._lines[uri] = Lines(self.texts.get(uri, ""), self.encoding)
        return self._lines[uri]

    def diagnostics(self) -> list[Diagnostic]:
        """The diagnostics of the document itself (its domain's are published with the domain)."""
        return [d for d in (*self.analysis.diagnostics, *self.extra) if d.span.file == self.file]

    def symbol_at(self, line: int, column: int) -> Declaration | Reference | None:
        """The declaration or reference under the 1-based (``line``, ``column``) of the document."""
        found = self.analysis.index.symbol_at(self.file, line, column)
        if found is None and column > 1:  # the cursor just after a name still means that name
            found = self.analysis.index.symbol_at(self.file, line, column - 1)
        return found


class Analyses:
    """Analyses of documents, redone only when a text they read has changed."""

    def __init__(self, files: Files):
        self.files = files
        self.encoding = UTF16  # the position encoding agreed at initialize (the server sets it)
        self._kept: dict[str, Checked] = {}
        self._words: dict[str, tuple[str, set[str]]] = {}  # problem uri -> (text, its words)

    def of(self, uri: str) -> Checked | None:
        """The analysis of ``uri`` (a domain or problem), None for a plan, a file not found, or a file that
        is neither ``.pddl`` nor begins with ``(define (domain|problem`` (an editor may send any text)."""
        text = self.files.text(uri)
        if text is None:
            return None
        header = self.files.header(uri)
        if header.kind == PLAN:
            return self._plan(uri, text)
        if not header.kind and not uri.lower().endswith(".pddl"):
            return None
        domain_uri = uri if header.kind != PROBLEM else self.files.domain_for(uri)
        texts = {uri: text}
        if domain_uri is not None and domain_uri != uri:
            domain_text = self.files.text(domain_uri)
            if domain_text is None:
                domain_uri = None
            else:
                texts[domain_uri] = domain_text
        kept = self._kept.get(uri)
        if kept is not None and kept.texts == texts and kept.domain_uri == domain_uri:
            return kept
        checked = self._check(uri, header.kind or DOMAIN, domain_uri, texts, header.domain)
        self._kept.pop(uri, None)
        self._kept[uri] = checked
        while len(self._kept) > _KEPT:
            del self._kept[next(iter(self._kept))]
        return checked

    def names_in_problems(self, checked: Checked) -> set[str]:
        """The names (lower case) written in a domain's problems, open or beside it: a type or predicate the
        domain alone never uses is no "unused" warning when a problem names it. Read as words, not
        analysed: a domain edit then costs one analysis, however many problems sit beside it."""
        names: set[str] = set()
        if checked.kind != DOMAIN:
            return names
        for problem in self.files.problems_of(checked.uri):
            text = self.files.text(problem) or ""
            kept = self._words.get(problem)
            if kept is None or kept[0] is not text and kept[0] != text:
                kept = (text, {w.lower() for w in _WORD.findall(_COMMENT.sub(" ", text))})
                self._words[problem] = kept
            names |= kept[1]
        return names

    def forget(self, uri: str) -> None:
        self._kept.pop(uri, None)

    def _plan(self, uri: str, text: str) -> Checked | None:
        """A plan checked against a problem of its folder (an open one first, the most recent; then the
        folder's files by name; then problems open elsewhere) and that problem's domain: each step's
        action, arity, objects and their types."""
        folder = Path(path_of(uri)).parent
        for other in sorted(self.files.neighbours(uri), key=lambda u: Path(path_of(u)).parent != folder):
            if self.files.header(other).kind != PROBLEM:
                continue
            problem = self.of(other)
            if problem is None or problem.domain_uri is None:
                continue
            texts = {uri: text, **problem.texts}
            kept = self._kept.get(uri)
            if kept is not None and kept.texts == texts and kept.domain_uri == problem.domain_uri:
                return kept
            steps = analyse_plan(problem.analysis, text, path_of(uri))
            uris = {path_of(u): u for u in texts}
            checked = Checked(
                uri, PLAN, problem.domain_uri, problem.analysis, texts, steps.diagnostics, uris, self.encoding
            )
            self._kept.pop(uri, None)
            self._kept[uri] = checked
            return checked
        return None

    def _check(self, uri: str, kind: str, domain_uri: str | None, texts: dict[str, str], wanted: str) -> Checked:
        uris = {path_of(u): u for u in texts}
        too_deep = nested_too_deeply(texts[uri], path_of(uri))
        if too_deep is not None:
            analysis = Analysis([], Index())
            return Checked(uri, kind, domain_uri, analysis, texts, [too_deep], uris, self.encoding)
        if domain_uri is not None and domain_uri != uri and nested_too_deeply(texts[domain_uri], "") is not None:
            domain_uri = None  # the domain shows its own error; the problem is read alone
            texts = {uri: texts[uri]}
        if kind == PROBLEM and domain_uri is not None:
            analysis = analyse(texts[domain_uri], path_of(domain_uri), texts[uri], path_of(uri))
        else:
            analysis = analyse(texts[uri], path_of(uri))
        checked = Checked(uri, kind, domain_uri, analysis, texts, _uris=uris, encoding=self.encoding)
        if kind == PROBLEM:
            checked.extra.extend(self._which_domain(checked))
        if kind == PROBLEM and domain_uri is None and wanted:
            checked.extra.append(self._no_domain(checked, wanted))
        return checked

    def _which_domain(self, checked: Checked) -> list[Diagnostic]:
        """A warning at ``(:domain NAME)`` when several files define that domain and the problem has not
        chosen (naming them, with a quick fix per file that writes the ``;; !domain: FILE`` comment);
        one at the comment when the file it chooses is not there."""
        at = self._domain_reference(checked)
        chosen = self.files.chosen_domain(checked.uri)
        folder = Path(checked.file).parent
        if chosen is not None:
            if self.files.text(chosen) is not None:
                return []
            line = next(i for i, text in enumerate(checked.texts[checked.uri].splitlines(), 1) if CHOSEN.match(text))
            span = Span(checked.file, line, 1, line, len(checked.texts[checked.uri].splitlines()[line - 1]) + 1)
            message = f"the ;; !domain: comment chooses {os.path.relpath(path_of(chosen), folder)}, which is not there"
            return [Diagnostic(span, WARNING, message, "chosen-domain-missing")]
        candidates = self.files.domain_candidates(checked.uri)
        if len(candidates) < 2:
            return []
        names = [os.path.relpath(path_of(c), folder) for c in candidates]
        name = self.files.header(checked.uri).domain
        message = (
            f"{len(names)} files define domain '{name}': {', '.join(names)}; this problem is checked against "
            f"{names[0]}: choose one with a ';; !domain: FILE' comment at the top (quick fix)"
        )
        top = Span(checked.file, 1, 1, 1, 1)
        fixes = tuple(Fix(f"check against {n} (;; !domain: {n})", top, f";; !domain: {n}\n") for n in names)
        return [Diagnostic(at, WARNING, message, "several-domains", None, fixes)]

    @staticmethod
    def _domain_reference(checked: Checked) -> Span:
        """Where the problem's ``(:domain NAME)`` names its domain (its first line when it does not)."""
        return next(
            (r.span for r in checked.analysis.index.references if r.kind == "domain" and r.span.file == checked.file),
            Span(checked.file, 1, 1, 1, 1),
        )

    def _no_domain(self, checked: Checked, wanted: str) -> Diagnostic:
        """A warning at the problem's ``(:domain NAME)``: no open document or file of its folder defines it."""
        at = self._domain_reference(checked)
        names = [self.files.header(u).name for u in self.files.domains_near(checked.uri)]
        suggestion = closest(wanted, names)
        message = (
            f"no domain '{wanted}' among the open documents and the .pddl files of this folder; "
            "only the problem's syntax is checked (open its domain or put it beside the problem)"
        )
        fixes = (Fix(f"change to '{suggestion}'", at, suggestion),) if suggestion else ()
        return Diagnostic(at, WARNING, message, "domain-not-found", suggestion, fixes)


def nested_too_deeply(text: str, file: str) -> Diagnostic | None:
    """An error at the first parenthesis nested deeper than :data:`NESTING_LIMIT` (comments skipped),
    None when ``text`` nests no deeper. Counted in one pass, without recursion."""
    if text.count("(") <= NESTING_LIMIT:
        return None
    depth = 0
    for found in _PARENTHESIS.finditer(text):
        mark = found.group()
        if mark == "(":
            depth += 1
            if depth > NESTING_LIMIT:
                offset = found.start()
                line = text.count("\n", 0, offset) + 1
                column = offset - (text.rfind("\n", 0, offset) + 1) + 1
                message = (
                    f"nested too deeply (limit {NESTING_LIMIT}): this parenthesis opens level {depth}; "
                    "the document is not analysed until it nests less"
                )
                return Diagnostic(Span(file, line, column, line, column + 1), ERROR, message, "nested-too-deeply")
        elif mark == ")":
            depth = max(0, depth - 1)
    return None
