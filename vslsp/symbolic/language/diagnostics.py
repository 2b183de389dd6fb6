"""What the PDDL language engine reports: places (:class:`Span`), :class:`Diagnostic` s, quick fixes
(:class:`Fix`) and the did-you-mean rule (:func:`closest`).

Places are 1-based lines and columns, the end exclusive (the column just after the last character),
counted in characters; a language server subtracts 1 from each (LSP positions are 0-based).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any, NamedTuple

from vslsp.symbolic.budget import MAX_SUGGESTION_COMPARISONS

ERROR = "error"
WARNING = "warning"


class Span(NamedTuple):
    """A range of one file: from (``line``, ``column``) up to, not including, (``end_line``, ``end_column``)."""

    file: str
    line: int
    column: int
    end_line: int
    end_column: int

    def contains(self, line: int, column: int) -> bool:
        """Whether the character at (``line``, ``column``) lies in the span (its end included, for a cursor)."""
        if (line, column) < (self.line, self.column):
            return False
        return (line, column) <= (self.end_line, self.end_column)

    def to(self, other: Span) -> Span:
        """From the start of this span to the end of ``other``."""
        return Span(self.file, self.line, self.column, other.end_line, other.end_column)


@dataclass(frozen=True, slots=True)
class Fix:
    """A quick fix: replace ``span`` by ``text`` (an empty span inserts); ``title`` says what it does."""

    title: str
    span: Span
    text: str

    def to_dict(self) -> dict[str, Any]:
        s = self.span
        return {
            "title": self.title,
            "file": s.file,
            "line": s.line,
            "column": s.column,
            "end_line": s.end_line,
            "end_column": s.end_column,
            "text": self.text,
        }


@dataclass(frozen=True, slots=True)
class Diagnostic:
    """One error or warning, located at the token the user typed.

    ``code`` names the kind (``unknown-predicate``, ``unclosed-parenthesis`` ...: stable, for tools);
    ``suggestion`` is the declared name closest to an unknown one (None where none is close);
    ``fixes`` are edits a language server offers (the did-you-mean replacement first).
    """

    span: Span
    severity: str
    message: str
    code: str
    suggestion: str | None = None
    fixes: tuple[Fix, ...] = ()

    @property
    def file(self) -> str:
        return self.span.file

    @property
    def line(self) -> int:
        return self.span.line

    @property
    def column(self) -> int:
        return self.span.column

    @property
    def is_error(self) -> bool:
        return self.severity == ERROR

    def format(self) -> str:
        """``FILE:LINE:COL: error|warning: message (did you mean 'x'?)``."""
        hint = f" (did you mean '{self.suggestion}'?)" if self.suggestion else ""
        return f"{self.span.file}:{self.span.line}:{self.span.column}: {self.severity}: {self.message}{hint}"

    def to_dict(self) -> dict[str, Any]:
        """The JSON of ``vslsp pddl check --json`` (docs/cli.md)."""
        s = self.span
        return {
            "file": s.file,
            "line": s.line,
            "column": s.column,
            "end_line": s.end_line,
            "end_column": s.end_column,
            "severity": self.severity,
            "message": self.message,
            "suggestion": self.suggestion,
            "code": self.code,
            "fixes": [fix.to_dict() for fix in self.fixes],
        }


def sort_key(diagnostic: Diagnostic) -> tuple[str, int, int, str]:
    return (diagnostic.span.file, diagnostic.span.line, diagnostic.span.column, diagnostic.message)


def distance(a: str, b: str, limit: int) -> int:
    """The optimal-string-alignment distance of ``a`` and ``b`` (insertions, deletions, substitutions,
    swaps of neighbours: ``claen`` -> ``clean`` is 1), or ``limit + 1`` once it must exceed ``limit``."""
    if abs(len(a) - len(b)) > limit:
        return limit + 1
    previous2: list[int] = []
    previous = list(range(len(b) + 1))
    for i in range(1, len(a) + 1):
        current = [i] + [0] * len(b)
        for j in range(1, len(b) + 1):
            cost = 0 if a[i - 1] == b[j - 1] else 1
            value = min(previous[j] + 1, current[j - 1] + 1, previous[j - 1] + cost)
            if i > 1 and j > 1 and a[i - 1] == b[j - 2] and a[i - 2] == b[j - 1]:
                value = min(value, previous2[j - 2] + 1)
            current[j] = value
        if min(current) > limit:
            return limit + 1
        previous2, previous = previous, current
    return previous[-1]


class SuggestionBudget:
    """How many candidate names the did-you-mean suggestions of one check may still compare
    (:data:`~vslsp.symbolic.budget.MAX_SUGGESTION_COMPARISONS`); past it, :func:`closest` suggests none."""

    def __init__(self, comparisons: int = MAX_SUGGESTION_COMPARISONS) -> None:
        self.left = comparisons

    def take(self, count: int) -> bool:
        """Spend ``count`` comparisons if that many are left."""
        if count > self.left:
            return False
        self.left -= count
        return True


def closest(name: str, candidates: Iterable[str], budget: SuggestionBudget | None = None) -> str | None:
    """The candidate nearest to ``name`` (case ignored) when it is close enough to be a typo: at most
    one edit for names of 3 or 4 characters, two up to 8, three beyond (none for shorter names: any
    one-letter name is one edit from any other); ties go to the first candidate. With a ``budget``, none
    once it is spent."""
    key = name.lower()
    if len(key) < 3:
        return None
    if budget is not None:
        candidates = candidates if isinstance(candidates, (list, tuple)) else list(candidates)
        if not budget.take(len(candidates)):
            return None
    limit = 1 if len(key) <= 4 else 2 if len(key) <= 8 else 3
    best: str | None = None
    best_distance = limit + 1
    for candidate in candidates:
        lowered = candidate.lower()
        if lowered == key:
            continue
        found = distance(key, lowered, min(limit, best_distance - 1) if best is not None else limit)
        if found < best_distance:
            best, best_distance = candidate, found
    return best
