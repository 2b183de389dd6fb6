"""Clear errors for malformed PDDL: ``FILE:LINE:COL: what is wrong``.

unified-planning's reader reports problems in several shapes (pyparsing exceptions, Python
``SyntaxError`` with "line: L, col C" in the text, its own exceptions without a place). This
module checks what a reader cannot explain well (unbalanced parentheses, the paper's
non-PDDL ``somewhere-after``, unsupported constructs, type cycles) before parsing, rewrites
what the reader cannot take (preferences, ``at end``) and the reader's errors after.
"""

from __future__ import annotations

import re
import warnings

from vslsp.errors import InputError


class PddlWarning(UserWarning):
    """Something in a PDDL file vslsp reads differently from the letter of PDDL, or ignores."""


def warn(message: str) -> None:
    """Issue a :class:`PddlWarning` (the CLI prints them as ``warning: ...``)."""
    warnings.warn(message, PddlWarning, stacklevel=3)

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
    for match in re.finditer(r"\(\s*(within|always-within|hold-during|hold-after)\b", code, re.IGNORECASE):
        if re.search(r"\(\s*problem\b", code, re.IGNORECASE):
            line, column = _position(text, match.start(1))
            raise InputError(f"{name}:{line}:{column}: ({match.group(1).lower()} ...) is not supported (timed "
                             "constraints need a temporal planner); vslsp plans with always, sometime, at-most-once, "
                             "sometime-before, sometime-after and at end")
    for match in re.finditer(r"\(\s*(either|:derived|:functions|:durative-action)\b", code, re.IGNORECASE):
        word = match.group(1).lower()
        if word == ":functions" and re.match(r"\(\s*:functions\s*\(\s*total-cost\s*\)(\s*-\s*number)?\s*\)",
                                             code[match.start():], re.IGNORECASE):
            continue  # action costs: read, and ignored by the planners vslsp uses
        line, column = _position(text, match.start(1))
        what = {"either": "(either ...) types", ":derived": "derived predicates (:derived ...)",
                ":functions": "numeric functions other than (total-cost)",
                ":durative-action": "durative actions"}[word]
        raise InputError(f"{name}:{line}:{column}: {what} are not supported; vslsp reads STRIPS with types, "
                         "negation, equality, quantifiers, conditional effects, constants and PDDL 3.0 constraints")
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
    """Warn when the problem's ``(:domain NAME)`` is not the domain read with it (VAL and Fast Downward accept it)."""
    match = re.search(r"\(\s*:domain\s+([^\s()]+)", _code(problem_text), re.IGNORECASE)
    if match and match.group(1).lower() != domain_name.lower():
        line, column = _position(problem_text, match.start(1))
        warn(f"{name}:{line}:{column}: the problem is for domain {match.group(1)!r}, but the domain file "
             f"defines {domain_name!r}; read with it all the same")


def check_types(text: str, name: str) -> None:
    """Raise InputError, with the place, when the ``(:types ...)`` of a domain form a cycle."""
    code = _code(text)
    section = re.search(r"\(\s*:types\b([^()]*)\)", code, re.IGNORECASE)
    if not section:
        return
    parents: dict[str, tuple[str, int]] = {}
    pending: list[tuple[str, int]] = []
    tokens = list(re.finditer(r"[^\s]+", section.group(1)))
    index = 0
    while index < len(tokens):
        word = tokens[index].group(0).lower()
        if word == "-" and index + 1 < len(tokens):
            parent = tokens[index + 1].group(0).lower()
            for child, at in pending:
                parents[child] = (parent, at)
            pending, index = [], index + 2
            continue
        pending.append((word, section.start(1) + tokens[index].start()))
        index += 1
    for start in parents:
        seen, current = [start], start
        while current in parents:
            current = parents[current][0]
            if current == start:
                line, column = _position(text, parents[start][1])
                raise InputError(f"{name}:{line}:{column}: the types form a cycle ({' - '.join([*seen, start])}); "
                                 "a type cannot be its own ancestor")
            if current in seen:
                break
            seen.append(current)


def preferences_removed(text: str, name: str) -> str:
    """``text`` with every ``(preference ...)`` replaced by ``(and)`` (and a ``:metric`` that weighs them
    removed), positions kept; warns once. vslsp plans for the hard goal and constraints."""
    code = _code(text)
    found = [m.start() for m in re.finditer(r"\(\s*preference\b", code, re.IGNORECASE)]
    if not found:
        return text
    spans = [(start, _closing(code, start)) for start in found]
    metric = re.search(r"\(\s*:metric\b", code, re.IGNORECASE)
    if metric and "is-violated" in code[metric.start():_closing(code, metric.start())].lower():
        spans.append((metric.start(), _closing(code, metric.start())))
    out = list(text)
    for start, end in spans:
        if out[start] != "(":  # inside a preference removed already
            continue
        blank = [c if c == "\n" else " " for c in text[start:end + 1]]
        blank[0:5] = list("(and)") if len(blank) >= 5 else blank[0:5]
        out[start:end + 1] = blank
    line, column = _position(text, found[0])
    warn(f"{name}:{line}:{column}: {len(found)} preference{'s' if len(found) != 1 else ''} ignored: vslsp plans for "
         "the hard goal and constraints only (soft goals and their :metric are left out)")
    return "".join(out)


def _closing(code: str, start: int) -> int:
    """The index of the ``)`` closing the ``(`` at ``start``."""
    depth = 0
    for index in range(start, len(code)):
        depth += {"(": 1, ")": -1}.get(code[index], 0)
        if depth == 0:
            return index
    return len(code) - 1


def at_end_as_sometime_after(text: str) -> str:
    """``(at end φ)`` in ``:constraints`` written as ``(sometime-after (and) φ)``: the same meaning, which
    unified-planning's reader takes (it has no ``at end``)."""
    return re.sub(r"\(\s*at\s+end\b", "(sometime-after (and)", text, flags=re.IGNORECASE)


def check_constraints_form(text: str, name: str) -> None:
    """Warn when ``(:constraints c1 c2 ...)`` lists constraints without ``(and ...)``."""
    code = _code(text)
    match = re.search(r"\(\s*:constraints\b", code, re.IGNORECASE)
    if not match:
        return
    body = code[match.end():_closing(code, match.start())]
    depth, tops = 0, 0
    for char in body:
        if char == "(":
            tops += depth == 0
            depth += 1
        elif char == ")":
            depth -= 1
    if tops > 1:
        line, column = _position(text, match.start())
        warn(f"{name}:{line}:{column}: (:constraints ...) lists {tops} constraints without (and ...); read as their "
             "conjunction (VAL drops such constraints)")


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
