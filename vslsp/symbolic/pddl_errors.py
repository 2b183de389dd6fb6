"""Clear errors for malformed PDDL: ``FILE:LINE:COL: what is wrong``.

unified-planning's reader reports problems in several shapes (pyparsing exceptions, Python
``SyntaxError`` with "line: L, col C" in the text, its own exceptions without a place). This
module checks what a reader cannot explain well (unbalanced parentheses, the paper's
non-PDDL ``somewhere-after``) before parsing, and rewrites the reader's errors after.
"""

from __future__ import annotations

import re

from vslsp.errors import InputError

PDDL3_OPERATORS = ("always", "sometime", "within", "at-most-once", "sometime-after", "sometime-before",
                   "always-within", "hold-during", "hold-after", "at end")
_NOT_PDDL = {
    "somewhere-after": "PDDL 3.0 has no 'somewhere-after'; for \"p only after q\" (the demonstrated order) "
                       "write (sometime-before p q)",
    "somewhere-before": "PDDL 3.0 has no 'somewhere-before'; for \"p only after q\" write (sometime-before p q)",
}


def _position(text: str, index: int) -> tuple[int, int]:
    """1-based (line, column) of character ``index``."""
    line = text.count("\n", 0, index) + 1
    return line, index - (text.rfind("\n", 0, index) + 1) + 1


def _code(text: str) -> str:
    """``text`` with comments blanked out (same length, so positions stay)."""
    return re.sub(r";[^\n]*", lambda m: " " * len(m.group(0)), text)


def check_text(text: str, name: str) -> None:
    """Raise InputError for unbalanced parentheses and non-PDDL operators, with their place."""
    code = _code(text)
    for match in re.finditer(r"\(\s*(somewhere-after|somewhere-before)\b", code, re.IGNORECASE):
        line, column = _position(text, match.start(1))
        raise InputError(f"{name}:{line}:{column}: {_NOT_PDDL[match.group(1).lower()]}. "
                         f"The PDDL 3.0 operators are: {', '.join(PDDL3_OPERATORS)}")
    for match in re.finditer(r"\(\s*(at\s+end|within|always-within|hold-during|hold-after)\b", code, re.IGNORECASE):
        if re.search(r"\(\s*problem\b", code, re.IGNORECASE):
            line, column = _position(text, match.start(1))
            operator = " ".join(match.group(1).lower().split())
            hint = "put the formula in the (:goal ...), which means the same" if operator == "at end" else \
                "timed constraints need a temporal planner"
            raise InputError(f"{name}:{line}:{column}: ({operator} ...) is not supported here ({hint}); vslsp plans "
                             f"with always, sometime, at-most-once, sometime-before and sometime-after")
    opened: list[int] = []
    for index, char in enumerate(code):
        if char == "(":
            # A section keyword such as (:action or (:goal belongs at depth 1, inside (define ...).
            if code.startswith("(:", index) and len(opened) > 1:
                line, column = _position(text, index)
                open_line, open_column = _position(text, opened[-1])
                keyword = re.match(r"\(:[\w-]+", code[index:]).group(0)  # type: ignore[union-attr]
                raise InputError(f"{name}:{line}:{column}: '{keyword}' starts inside an unclosed '(' "
                                 f"(opened at line {open_line}, col {open_column}): a ')' is missing before it")
            opened.append(index)
        elif char == ")":
            if not opened:
                line, column = _position(text, index)
                raise InputError(f"{name}:{line}:{column}: unexpected ')': there is no '(' left to close; "
                                 "remove it or add the missing '('")
            opened.pop()
    if opened:
        line, column = _position(text, opened[-1])
        raise InputError(f"{name}:{line}:{column}: this '(' is never closed: a ')' is missing "
                         f"({len(opened)} unclosed at the end of the file)")
    if not code.strip():
        raise InputError(f"{name}: the file is empty; expected (define (domain ...)) or (define (problem ...))")


def check_domain_name(problem_text: str, domain_name: str, name: str) -> None:
    """Raise InputError when the problem's ``(:domain NAME)`` is not the domain read with it."""
    match = re.search(r"\(\s*:domain\s+([^\s()]+)", _code(problem_text), re.IGNORECASE)
    if match and match.group(1).lower() != domain_name.lower():
        line, column = _position(problem_text, match.start(1))
        raise InputError(f"{name}:{line}:{column}: the problem is for domain {match.group(1)!r}, but the domain file "
                         f"defines {domain_name!r}; give the matching domain file or fix (:domain ...)")


_ORDER = {
    "domain": ":requirements, :types, :constants, :predicates, :functions, :constraints, then the actions",
    "problem": ":domain, :requirements, :objects, :init, :goal, :constraints, :metric",
}
_PLACE = re.compile(r"line:?\s*(\d+),\s*col:?\s*(\d+)", re.IGNORECASE)
_REWRITES = (
    (re.compile(r"Not able to handle: \(\s*([^\s()]+)"), "unknown predicate or operator '{0}'"),
    (re.compile(r"Found invalid expression: ([^\s.]+)"), "unknown object or constant '{0}'"),
    (re.compile(r"Undefined parameter's type: ([^\s.]+)"), "undefined type '{0}'"),
    (re.compile(r"Undefined variable's type: ([^\s.]+)"), "undefined type '{0}'"),
    (re.compile(r"Undefined name found: ([^\s.]+)"), "undefined parameter '?{0}'"),
    (re.compile(r"fluent: (\S+) has arity (\d+) but (\d+) parameters"), "'{0}' takes {1} argument(s), {2} given"),
    (re.compile(r"The expression '([^']+)' is not well-formed"),
     "type error in {0}: an argument's type does not match the predicate's parameter type"),
    (re.compile(r"Type (\S+) is declared more than once"), "type '{0}' is declared more than once"),
    (re.compile(r"Missing goal section"), "the problem has no (:goal ...) section"),
)


def located_error(error: Exception, text: str, name: str) -> InputError:
    """An InputError ``NAME:LINE:COL: what`` from an exception raised by unified-planning's reader."""
    message = str(error)
    line, column = getattr(error, "lineno", None), getattr(error, "col", None)
    if type(error).__name__ in ("ParseException", "ParseSyntaxException"):
        found = re.sub(r"\s*\(at char \d+\), \(line:\d+, col:\d+\)", "", getattr(error, "msg", message))
        what = f"syntax error: {found}"
        section = re.match(r"\(:[\w-]+", text[getattr(error, "loc", 0):])
        if section:
            kind = "problem" if re.search(r"\(\s*problem", text, re.IGNORECASE) else "domain"
            what = f"{what}: '{section.group(0)}' is not allowed here; sections come in the order {_ORDER[kind]}"
    else:
        place = _PLACE.search(message)
        if place:
            line, column = int(place.group(1)), int(place.group(2))
        what = message.splitlines()[0].strip() if message else type(error).__name__
        for pattern, template in _REWRITES:
            match = pattern.search(message)
            if match:
                what = template.format(*match.groups())
                break
        if not place:
            line, column = _guess_place(what, text)
    where = f"{name}:{line}:{column}" if line else name
    return InputError(f"{where}: {what}")


def _guess_place(what: str, text: str) -> tuple[int | None, int | None]:
    """The first place in ``text`` where the quoted name of ``what`` appears (case-insensitive)."""
    quoted = re.search(r"'\??([^']+)'", what)
    if quoted:
        found = re.search(rf"(?<![\w-]){re.escape(quoted.group(1))}(?![\w-])", text, re.IGNORECASE)
        if found:
            return _position(text, found.start())
    return None, None
