"""Places in a document: the engine's 1-based line and character columns against LSP's 0-based lines and
UTF-16 code units (LSP 3.17's default position encoding; PDDL is mostly ASCII, where both agree)."""

from __future__ import annotations

from lsprotocol import types

from vslsp.symbolic.language.diagnostics import Span


class Lines:
    """The lines of one text, to convert columns between characters and UTF-16 units."""

    def __init__(self, text: str):
        self.text = text
        self._lines = text.split("\n")
        self._ascii = text.isascii()

    def line(self, number: int) -> str:
        """Line ``number`` (1-based), "" beyond the end."""
        return self._lines[number - 1] if 0 < number <= len(self._lines) else ""

    def position(self, line: int, column: int) -> types.Position:
        """LSP position of the 1-based (``line``, ``column``) (a character column)."""
        if self._ascii:
            return types.Position(line - 1, column - 1)
        prefix = self.line(line)[: column - 1]
        return types.Position(line - 1, len(prefix.encode("utf-16-le")) // 2)

    def range(self, span: Span) -> types.Range:
        return types.Range(self.position(span.line, span.column), self.position(span.end_line, span.end_column))

    def place(self, position: types.Position) -> tuple[int, int]:
        """1-based (line, character column) of an LSP position (past the line's end: its end)."""
        line = position.line + 1
        text = self.line(line)
        if self._ascii:
            return line, min(position.character, len(text)) + 1
        units = 0
        for index, char in enumerate(text):
            if units >= position.character:
                return line, index + 1
            units += 2 if ord(char) > 0xFFFF else 1
        return line, len(text) + 1

    def offset(self, position: types.Position) -> int:
        """0-based character offset of an LSP position in the text."""
        line, column = self.place(position)
        return sum(len(text) + 1 for text in self._lines[: line - 1]) + column - 1
