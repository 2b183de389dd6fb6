"""Places in a document: the engine's 1-based line and character columns against LSP's 0-based lines and
columns in the code units the client and server agreed on at initialize (``utf-16``, LSP's default;
``utf-8``, which Neovim prefers; ``utf-32``, characters). PDDL is mostly ASCII, where all agree.
"""

from __future__ import annotations

from lsprotocol import types

from vslsp.symbolic.language.diagnostics import Span

UTF16 = "utf-16"


def units(text: str, encoding: str = UTF16) -> int:
    """How many code units of ``encoding`` ``text`` takes."""
    if encoding == "utf-8":
        return len(text.encode("utf-8"))
    if encoding == "utf-32":
        return len(text)
    return len(text.encode("utf-16-le")) // 2


def characters(line: str, count: int, encoding: str = UTF16) -> int:
    """The character column reached after ``count`` code units of ``line`` (past its end: its length)."""
    if line.isascii():
        return min(count, len(line))
    total = 0
    for index, char in enumerate(line):
        if total >= count:
            return index
        total += units(char, encoding)
    return len(line)


class Lines:
    """The lines of one text, to convert columns between characters and the client's code units."""

    def __init__(self, text: str, encoding: str = UTF16):
        self.text = text
        self.encoding = encoding
        self._lines = text.split("\n")
        self._ascii = text.isascii()

    def line(self, number: int) -> str:
        """Line ``number`` (1-based), "" beyond the end."""
        return self._lines[number - 1] if 0 < number <= len(self._lines) else ""

    def position(self, line: int, column: int) -> types.Position:
        """LSP position of the 1-based (``line``, ``column``) (a character column)."""
        if self._ascii:
            return types.Position(line - 1, column - 1)
        return types.Position(line - 1, units(self.line(line)[: column - 1], self.encoding))

    def range(self, span: Span) -> types.Range:
        return types.Range(self.position(span.line, span.column), self.position(span.end_line, span.end_column))

    def place(self, position: types.Position) -> tuple[int, int]:
        """1-based (line, character column) of an LSP position (past the line's end: its end)."""
        line = position.line + 1
        return line, characters(self.line(line), position.character, self.encoding) + 1

    def offset(self, position: types.Position) -> int:
        """0-based character offset of an LSP position in the text."""
        line, column = self.place(position)
        return sum(len(text) + 1 for text in self._lines[: line - 1]) + column - 1


def clamped(text: str, position: types.Position, encoding: str = UTF16) -> types.Position:
    """``position`` inside ``text``: a character past its line's end is that end, a line past the last
    the end of the text (LSP 3.17, "Position")."""
    lines = text.count("\n")
    if position.line > lines:
        last = text[text.rfind("\n") + 1 :]
        return types.Position(lines, units(last, encoding))
    start = 0
    for _ in range(position.line):
        start = text.index("\n", start) + 1
    end = text.find("\n", start)
    line = text[start : end if end >= 0 else len(text)]
    length = len(line) if line.isascii() else units(line, encoding)
    return position if position.character <= length else types.Position(position.line, length)
