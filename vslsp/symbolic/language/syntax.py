"""The reader of the PDDL language engine: tokens with positions and the tree of parentheses.

PDDL is a list language (McDermott et al. 1998; Gerevini & Long 2005 for PDDL 3.0), so reading is
two linear passes: :func:`tokenize` cuts the text into parentheses, names and comments, each with
its line and column, and :func:`build_tree` nests the tokens into :class:`Group` s. A parenthesis
that never closes or a ``)`` with nothing to close is reported as a :class:`Diagnostic` at the
character the user typed, and the tree is repaired (closed at the end of the line the indentation
says the list ended on) so that the rest of the file is still checked.
"""

from __future__ import annotations

import gc
import re
from bisect import bisect_left
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field

from vslsp.symbolic.budget import MAX_NESTING, nested_too_deeply
from vslsp.symbolic.language.diagnostics import ERROR, Diagnostic, Span

_new_span = tuple.__new__  # a Span without NamedTuple's Python-level constructor: one per token read
_SPACED_TOKEN = re.compile(r"(\s*)([()]|;[^\n]*|[^\s();]+)")


@dataclass(slots=True, eq=False)
class Token:
    """One token: ``kind`` is ``"("``, ``")"``, ``"name"`` (a name, ``?variable``, ``:keyword``, number
    or ``-``) or ``"comment"``; ``text`` as written, ``key`` in lower case (PDDL ignores case);
    ``line``/``column`` 1-based, ``offset`` 0-based in the document's text."""

    kind: str
    text: str
    key: str
    line: int
    column: int
    offset: int
    file: str

    @property
    def end_column(self) -> int:
        """The column just after the token (tokens never span lines)."""
        return self.column + len(self.text)

    @property
    def span(self) -> Span:
        return _new_span(Span, (self.file, self.line, self.column, self.line, self.column + len(self.text)))


@dataclass(slots=True, eq=False)
class Group:
    """A parenthesised list: its ``(`` and ``)`` tokens (``close`` None when it never closes) and items."""

    open: Token
    close: Token | None
    items: list[Token | Group] = field(default_factory=list)
    #: The head's lower-case text, or "" when the list does not start with a name.
    key: str = ""

    @property
    def head(self) -> Token | None:
        """The first item when it is a name (``and``, a predicate, ``:action`` ...), else None."""
        first = self.items[0] if self.items else None
        return first if isinstance(first, Token) else None

    @property
    def span(self) -> Span:
        last = self.close or _last_token(self)
        return Span(self.open.file, self.open.line, self.open.column, last.line, last.end_column)


def _last_token(group: Group) -> Token:
    while group.items:
        last = group.items[-1]
        if isinstance(last, Token):
            return last
        if last.close is not None:
            return last.close
        group = last
    return group.open


def text_of(node: Token | Group, lower: bool = False) -> str:
    """The node as written, whitespace and comments normalised: ``(sometime-before (a) (b))``;
    ``lower``: in lower case (PDDL ignores case). Without recursion: a tree may be deep."""
    parts: list[str] = []
    stack: list[Token | Group | str] = [node]
    while stack:
        item = stack.pop()
        if isinstance(item, str):
            parts.append(item)
        elif isinstance(item, Token):
            parts.append(item.key if lower else item.text)
        else:
            stack.append(")")
            for index in range(len(item.items) - 1, -1, -1):
                stack.append(item.items[index])
                if index:
                    stack.append(" ")
            stack.append("(")
    return "".join(parts)


@dataclass(slots=True)
class Document:
    """One file read: its tokens (no comments), its comments, the top-level groups and the reader's diagnostics."""

    file: str
    text: str
    tokens: list[Token]
    comments: list[Token]
    groups: list[Group]
    diagnostics: list[Diagnostic]
    #: line -> the text of the comment on it (without the ``;``)
    comment_lines: dict[int, str] = field(default_factory=dict)
    #: the lines that hold a comment and no code
    comment_only_lines: set[int] = field(default_factory=set)

    def comment_above(self, line: int) -> str:
        """The comment lines just above ``line`` (no blank line or code between), else a comment at the
        end of ``line`` itself; "" when there is none."""
        lines: list[str] = []
        current = line - 1
        while current in self.comment_only_lines:
            lines.append(self.comment_lines[current])
            current -= 1
        if lines:
            return "\n".join(reversed(lines))
        return self.comment_lines.get(line, "")


@contextmanager
def gc_paused() -> Iterator[None]:
    """Python's cycle collector paused: it would walk every token made so far again and again, which
    makes reading grow faster than the file (the engine's structures hold no cycles; reference
    counting frees them)."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


def read_document(text: str, file: str) -> Document:
    """``text`` tokenized and nested (linear time); unbalanced parentheses reported and repaired."""
    with gc_paused():
        return _read_document(text, file)


def _read_document(text: str, file: str) -> Document:
    tokens, comments = tokenize(text, file)
    too_deep = _too_deep(tokens)
    groups, diagnostics = build_tree(tokens) if too_deep is None else ([], [too_deep])
    return Document(
        file,
        text,
        tokens,
        comments,
        groups,
        diagnostics,
        {c.line: c.text.lstrip(";").strip() for c in comments},
        {c.line for c in comments if c.column == 1 or not text[c.offset - c.column + 1 : c.offset].strip()},
    )


def tokenize(text: str, file: str) -> tuple[list[Token], list[Token]]:
    """The tokens and the comments of ``text``, in order, in time linear in its length (one regular
    expression pass; the whitespace before each token carries the line count)."""
    tokens: list[Token] = []
    comments: list[Token] = []
    # a name written again shares the strings of its first writing (a large problem names each object
    # several times): the tokens' memory grows with the tokens, not with their letters
    seen: dict[str, tuple[str, str]] = {}
    line, line_start, offset = 1, 0, 0
    for space, word in _SPACED_TOKEN.findall(text):
        if space:
            newlines = space.count("\n")
            if newlines:
                line += newlines
                line_start = offset + space.rindex("\n") + 1
            offset += len(space)
        first = word[0]
        if first == ";":  # a CRLF file's comment ends before its \r, which still counts in the offsets
            comment = word.rstrip("\r")
            comments.append(Token("comment", comment, comment, line, offset - line_start + 1, offset, file))
        elif first == "(" or first == ")":
            tokens.append(Token(first, first, first, line, offset - line_start + 1, offset, file))
        else:
            shared = seen.get(word)
            if shared is None:
                key = word.lower()
                shared = seen[word] = (word, word if key == word else key)
            tokens.append(Token("name", shared[0], shared[1], line, offset - line_start + 1, offset, file))
        offset += len(word)
    return tokens, comments


def _too_deep(tokens: list[Token]) -> Diagnostic | None:
    """An error at the first ``(`` nested deeper than :data:`MAX_NESTING`, or None. Such a file is not
    nested into a tree at all: every check after reading walks the tree, one call per level."""
    depth = 0
    for token in tokens:
        if token.kind == "(":
            depth += 1
            if depth > MAX_NESTING:
                return Diagnostic(token.span, ERROR, nested_too_deeply(depth, MAX_NESTING), "too-deep")
        elif token.kind == ")":
            depth = max(depth - 1, 0)
    return None


@dataclass(slots=True)
class _Nesting:
    top: list[Group]
    unclosed: list[Group]  # still open at the end, outermost first
    extra: list[Token]  # a ')' with nothing to close, or a name outside any list
    left: list[tuple[Group, int, int]]  # (group, index of the token of the line that left it, depth)


def _nest(tokens: list[Token], close_before: set[int], skip: frozenset[int] = frozenset()) -> _Nesting:
    """Nest ``tokens``. A group is "left" by a later line that starts at or left of the indentation of
    the group's opening line while the group is the innermost open one (where a ``)`` was forgotten, if
    one was). A group is also closed just before each token index in ``close_before``, and the tokens at
    the indices in ``skip`` are left out (the repairs)."""
    top: list[Group] = []
    stack: list[Group] = []
    extra: list[Token] = []
    left: list[tuple[Group, int, int]] = []
    flagged: set[int] = set()
    indent: dict[int, int] = {}
    last_line = 0
    for index, token in enumerate(tokens):
        if index in skip:
            continue
        if index in close_before and stack:
            stack.pop()
        if token.line != last_line:
            last_line = token.line
            indent[token.line] = token.column
            if stack and token.kind != ")":
                inner = stack[-1]
                if (
                    inner.open.line < token.line
                    and indent[inner.open.line] >= token.column
                    and id(inner) not in flagged
                ):
                    flagged.add(id(inner))
                    left.append((inner, index, len(stack) - 1))
        if token.kind == "(":
            group = Group(token, None)
            (stack[-1].items if stack else top).append(group)
            stack.append(group)
        elif token.kind == ")":
            if stack:
                stack.pop().close = token
            else:
                extra.append(token)
        elif stack:
            inner = stack[-1]
            if not inner.items:
                inner.key = token.key
            inner.items.append(token)
        else:
            extra.append(token)
    return _Nesting(top, stack, extra, left)


def build_tree(tokens: list[Token]) -> tuple[list[Group], list[Diagnostic]]:
    """The top-level groups of ``tokens`` and a diagnostic for each parenthesis out of balance.

    A ``(`` left open is reported where the indentation says its list ended (the first list, below
    the top level, that a later line leaves), and the tree is closed there so that what follows is
    read as the user meant it; with no such hint, at the innermost ``(`` still open at the end.
    """
    nesting = _nest(tokens, set())
    diagnostics: list[Diagnostic] = []
    skip: frozenset[int] = frozenset()
    top = nesting.top
    if len(top) > 1 and top[0].key == "define" and top[0].close is not None and top[1].key.startswith(":"):
        # (define ...) closed before its sections end: one ')' too many where it closed
        early = top[0].close
        message = "unexpected ')': it closes (define ...) before its sections end; remove it"
        diagnostics.append(Diagnostic(early.span, ERROR, message, "unexpected-parenthesis"))
        skip = frozenset({bisect_left([t.offset for t in tokens], early.offset)})
        nesting = _nest(tokens, set(), skip)
    if nesting.unclosed:
        inner = [entry for entry in nesting.left if entry[2] >= 1] or nesting.left
        swallowing = _atom_swallowing_a_list(nesting.top, tokens)
        if swallowing is not None:
            inner = [(swallowing[0], swallowing[1], 1)]
        if inner:
            group, index, _ = inner[0]
            diagnostics.append(_unclosed(group))
            nesting = _nest(tokens, {index}, skip)
            reported = {id(group)}
        else:
            reported = set()
        for group in reversed(nesting.unclosed):
            if id(group) not in reported:
                diagnostics.append(_unclosed(group))
                break
    for token in nesting.extra:
        if token.kind == ")":
            message = "unexpected ')': there is no '(' left to close; remove it or add the missing '('"
            diagnostics.append(Diagnostic(token.span, ERROR, message, "unexpected-parenthesis"))
        else:
            message = f"'{token.text}' is outside any list; PDDL files are (define ...) lists"
            diagnostics.append(Diagnostic(token.span, ERROR, message, "outside-list"))
    return nesting.top, diagnostics


#: Heads of lists that hold lists; any other name heads an atom or a term, whose items are names.
_LIST_HEADS = frozenset(
    "define and or not imply exists forall when preference either = < > <= >= + - * / increase decrease "
    "assign scale-up scale-down at always sometime within at-most-once sometime-after sometime-before "
    "always-within hold-during hold-after minimize maximize is-violated".split()
)


def _atom_swallowing_a_list(top: list[Group], tokens: list[Token]) -> tuple[Group, int] | None:
    """The first atom such as ``(far red (far blue))`` (a predicate's arguments are names, so a list in
    it means its ``)`` was forgotten) and the index of the token where it should have closed."""
    stack = list(reversed(top))
    while stack:
        group = stack.pop()
        head = group.head
        children = [item for item in group.items if isinstance(item, Group)]
        atom = head is not None and not head.key.startswith(":") and head.key not in _LIST_HEADS
        if atom and any(child.key != "either" for child in children):  # (in ?x - (either a b)) is fine
            first = next(child for child in children if child.key != "either")
            return group, bisect_left([t.offset for t in tokens], first.open.offset)
        stack.extend(reversed(children))
    return None


def _unclosed(group: Group) -> Diagnostic:
    span = group.open.span
    head = group.head
    what = f"'({head.text}'" if head is not None else "this '('"
    message = f"{what} is never closed: a ')' is missing"
    return Diagnostic(span, ERROR, message, "unclosed-parenthesis")
