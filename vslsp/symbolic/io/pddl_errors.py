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
from vslsp.symbolic.budget import MAX_READER_NESTING, MAX_READER_TYPE_DEPTH, type_depths


class PddlWarning(UserWarning):
    """Something in a PDDL file vslsp reads differently from the letter of PDDL, or ignores."""


def warn(message: str) -> None:
    """Issue a :class:`PddlWarning` (the CLI prints them as ``warning: ...``)."""
    warnings.warn(message, PddlWarning, stacklevel=3)


PDDL3_OPERATORS = (
    "always",
    "sometime",
    "within",
    "at-most-once",
    "sometime-after",
    "sometime-before",
    "always-within",
    "hold-during",
    "hold-after",
    "at end",
)
#: The deepest parenthesis nesting read (unified-planning's reader recurses per level; ~50 overflow it).
MAX_NESTING = MAX_READER_NESTING
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
        raise InputError(
            f"{name}:{line}:{column}: {_NOT_PDDL[match.group(1).lower()]}. "
            f"The PDDL 3.0 operators are: {', '.join(PDDL3_OPERATORS)}"
        )
    for match in re.finditer(r"\(\s*(within|always-within|hold-during|hold-after)\b", code, re.IGNORECASE):
        if re.search(r"\(\s*problem\b", code, re.IGNORECASE):
            line, column = _position(text, match.start(1))
            raise InputError(
                f"{name}:{line}:{column}: ({match.group(1).lower()} ...) is not supported (timed "
                "constraints need a temporal planner); vslsp plans with always, sometime, at-most-once, "
                "sometime-before, sometime-after and at end"
            )
    predicates = _section_spans(code, ":predicates")
    for match in re.finditer(r"\(\s*(either|:derived|:functions|:durative-action)\b", code, re.IGNORECASE):
        word = match.group(1).lower()
        if word == "either" and any(start < match.start() < end for start, end in predicates):
            continue  # a predicate's parameter: widened to the types' common ancestor (either_widened)
        if word == ":functions" and re.match(
            r"\(\s*:functions\s*\(\s*total-cost\s*\)(\s*-\s*number)?\s*\)", code[match.start() :], re.IGNORECASE
        ):
            continue  # action costs: read, and ignored by the planners vslsp uses
        line, column = _position(text, match.start(1))
        what = {
            "either": "(either ...) types",
            ":derived": "derived predicates (:derived ...)",
            ":functions": "numeric functions other than (total-cost)",
            ":durative-action": "durative actions",
        }[word]
        raise InputError(
            f"{name}:{line}:{column}: {what} are not supported; vslsp reads STRIPS with types, "
            "negation, equality, quantifiers, conditional effects, constants and PDDL 3.0 constraints"
        )
    opened: list[int] = []
    for index, char in enumerate(code):
        if char == "(":
            # A section keyword such as (:action or (:goal belongs at depth 1, inside (define ...).
            if code.startswith("(:", index) and len(opened) > 1:
                line, column = _position(text, index)
                open_line, open_column = _position(text, opened[-1])
                keyword = re.match(r"\(:[\w-]+", code[index:]).group(0)  # type: ignore[union-attr]
                raise InputError(
                    f"{name}:{line}:{column}: '{keyword}' starts inside an unclosed '(' "
                    f"(opened at line {open_line}, col {open_column}): a ')' is missing before it"
                )
            opened.append(index)
            if len(opened) > MAX_NESTING:
                line, column = _position(text, index)
                raise InputError(
                    f"{name}:{line}:{column}: parentheses nest {len(opened)} deep here; vslsp's reader takes at "
                    f"most {MAX_NESTING} levels (flatten the formula: (and a (and b c)) is (and a b c))"
                )
        elif char == ")":
            if not opened:
                line, column = _position(text, index)
                raise InputError(
                    f"{name}:{line}:{column}: unexpected ')': there is no '(' left to close; "
                    "remove it or add the missing '('"
                )
            opened.pop()
    if opened:
        line, column = _position(text, opened[-1])
        raise InputError(
            f"{name}:{line}:{column}: this '(' is never closed: a ')' is missing "
            f"({len(opened)} unclosed at the end of the file)"
        )
    if not code.strip():
        raise InputError(f"{name}: the file is empty; expected (define (domain ...)) or (define (problem ...))")


def _section_spans(code: str, section: str) -> list[tuple[int, int]]:
    """(start, end) of every ``(section ...)`` in ``code`` (comments blanked)."""
    return [
        (match.start(), _closing(code, match.start()))
        for match in re.finditer(rf"\(\s*{re.escape(section)}\b", code, re.IGNORECASE)
    ]


def check_domain_name(problem_text: str, domain_name: str, name: str) -> None:
    """Raise InputError when the problem's ``(:domain NAME)`` is not the domain read with it: the files do
    not belong together (a plan for one would be checked against the other)."""
    match = re.search(r"\(\s*:domain\s+([^\s()]+)", _code(problem_text), re.IGNORECASE)
    if match and match.group(1).lower() != domain_name.lower():
        line, column = _position(problem_text, match.start(1))
        raise InputError(f"{name}:{line}:{column}: {other_domain(match.group(1), domain_name)}")


def other_domain(problem_domain: str, domain_name: str) -> str:
    """The message for a problem whose ``(:domain NAME)`` names another domain than the one given."""
    return (
        f"the problem is for domain {problem_domain!r}, but the domain file defines {domain_name!r}; "
        f"give the domain file of {problem_domain!r}, or write (:domain {domain_name}) in the problem"
    )


def either_widened(text: str, name: str) -> str:
    """``(either a b)`` as a predicate's parameter type replaced by the nearest common ancestor of a and b
    (positions kept as far as the text allows): a predicate's typing only says which atoms are well
    formed, and the atoms come from the files, so widening it changes no plan. Warns once."""
    code = _code(text)
    parents = {child: parent for child, (parent, _) in _type_parents(code).items()}

    def ancestors(type_: str) -> list[str]:
        chain, seen = [type_], {type_}
        while chain[-1] in parents and parents[chain[-1]] not in seen:
            chain.append(parents[chain[-1]])
            seen.add(chain[-1])
        return [*chain, "object"]

    found = list(re.finditer(r"\(\s*either\s+([^()]*)\)", code, re.IGNORECASE))
    for match in reversed(found):
        chains = [ancestors(t.lower()) for t in match.group(1).split()]
        others = [set(c) for c in chains[1:]]
        common = next((t for t in chains[0] if all(t in c for c in others)), "object")
        text = text[: match.start()] + common.ljust(match.end() - match.start()) + text[match.end() :]
    if found:
        line, column = _position(text, found[0].start())
        warn(f"{name}:{line}:{column}: (either ...) in a predicate's parameters read as the types' common ancestor")
    return text


_SECTION_ORDER = (":requirements", ":types", ":constants", ":predicates", ":functions", ":constraints")


def sections_in_order(text: str, name: str) -> str:
    """The domain with ``:types``, ``:constants``, ``:predicates`` ... moved into the order unified-planning's
    reader requires (PDDL does not; VAL and Fast Downward accept any). Warns when something moved."""
    code = _code(text)
    define = re.search(r"\(\s*define\b", code, re.IGNORECASE)
    if not define:
        return text
    end = _closing(code, define.start())
    sections, index = [], define.end()
    while True:
        start = code.find("(", index, end)
        if start < 0:
            break
        close = _closing(code, start)
        keyword = re.match(r"\(\s*([:\w-]+)", code[start:])
        sections.append((keyword.group(1).lower() if keyword else "", start, close))
        index = close + 1
    rank = [
        -1 if not k.startswith(":") else _SECTION_ORDER.index(k) if k in _SECTION_ORDER else len(_SECTION_ORDER)
        for k, _, _ in sections
    ]
    if rank == sorted(rank):
        return text
    ordered = [s for _, s in sorted(zip(rank, sections, strict=False), key=lambda pair: pair[0])]
    body = "\n".join(text[start : close + 1] for _, start, close in ordered)
    first = sections[0][1]
    moved = next(k for (k, _, _), r, sorted_r in zip(sections, rank, sorted(rank), strict=False) if r != sorted_r)
    warn(
        f"{name}: the domain's sections were read in the order {', '.join(_SECTION_ORDER)} ({moved} moved); "
        "places in later messages refer to that order"
    )
    return text[:first] + body + text[sections[-1][2] + 1 :]


def _type_parents(code: str) -> dict[str, tuple[str, int]]:
    """``{child: (parent, index of the child in code)}`` from the ``(:types ...)`` section."""
    section = re.search(r"\(\s*:types\b([^()]*)\)", code, re.IGNORECASE)
    parents: dict[str, tuple[str, int]] = {}
    if not section:
        return parents
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
    return parents


def types_declared_once(text: str) -> str:
    """The ``(:types ...)`` section rewritten one declaration per type when a type is declared after it
    served as a parent (``a - area  area - surface``: PDDL allows it, unified-planning's reader does not)."""
    code = _code(text)
    section = re.search(r"\(\s*:types\b([^()]*)\)", code, re.IGNORECASE)
    parents = _type_parents(code)
    if not section:
        return text
    words = section.group(1).lower().split()
    first_parent_use: dict[str, int] = {}
    for index, word in enumerate(words[:-1]):
        if word == "-":
            first_parent_use.setdefault(words[index + 1], index + 1)
    child_at = {w: i for i, w in enumerate(words) if w != "-" and (i == 0 or words[i - 1] != "-")}
    if not any(child_at.get(p, -1) > at for p, at in first_parent_use.items()):
        return text
    names = [w for w in words if w not in ("-", "object")]
    body = " ".join(f"{n} - {parents[n][0]}" if n in parents else n for n in dict.fromkeys(names))
    return text[: section.start(1)] + " " + body + text[section.end(1) :]


def check_types(text: str, name: str) -> None:
    """Raise InputError, with the place, when the ``(:types ...)`` of a domain form a cycle or a chain
    deeper than :data:`~vslsp.symbolic.budget.MAX_READER_TYPE_DEPTH` (both found in time linear in the types)."""
    parents = _type_parents(_code(text))
    if not parents:
        return
    walk_of: dict[str, int] = {}
    for walk, start in enumerate(parents):
        current: str | None = start
        path: list[str] = []
        while current is not None and current not in walk_of:
            walk_of[current] = walk
            path.append(current)
            current = parents[current][0] if current in parents else None
        if current is not None and walk_of[current] == walk:
            cycle = path[path.index(current) :]
            line, column = _position(text, parents[cycle[0]][1])
            raise InputError(
                f"{name}:{line}:{column}: the types form a cycle ({' - '.join([*cycle, cycle[0]])}); "
                "a type cannot be its own ancestor"
            )
    depths = type_depths({child: (parent,) for child, (parent, _) in parents.items()})
    deepest = max(depths.values(), default=0)
    if deepest > MAX_READER_TYPE_DEPTH:
        over = next(child for child in parents if depths[child] > MAX_READER_TYPE_DEPTH)
        line, column = _position(text, parents[over][1])
        raise InputError(
            f"{name}:{line}:{column}: the type hierarchy is {deepest} types deep: nested too deeply "
            f"(limit {MAX_READER_TYPE_DEPTH} on the planner's path); give the types fewer levels of parents"
        )


def preferences_removed(text: str, name: str) -> str:
    """``text`` with every ``(preference ...)`` replaced by ``(and)`` (and a ``:metric`` that weighs them
    removed), positions kept; warns once. vslsp plans for the hard goal and constraints."""
    code = _code(text)
    found = [m.start() for m in re.finditer(r"\(\s*preference\b", code, re.IGNORECASE)]
    if not found:
        return text
    spans = [(start, _closing(code, start)) for start in found]
    metric = re.search(r"\(\s*:metric\b", code, re.IGNORECASE)
    out = list(text)
    section = re.search(r"\(\s*:constraints\b", code, re.IGNORECASE)
    inside = (section.start(), _closing(code, section.start())) if section else (-1, -1)
    for start, end in spans:
        if out[start] != "(":  # inside a preference removed already
            continue
        blank = [c if c == "\n" else " " for c in text[start : end + 1]]
        if not inside[0] < start < inside[1]:
            blank[0:5] = list("(and)")  # a goal or precondition part: true
        out[start : end + 1] = blank
    if metric and "is-violated" in code[metric.start() : _closing(code, metric.start())].lower():
        end = _closing(code, metric.start())
        out[metric.start() : end + 1] = [c if c == "\n" else " " for c in text[metric.start() : end + 1]]
    if section:  # emptied (and ...) and (forall (...) ...) go, and the section if nothing is left
        empty = re.compile(r"\(\s*(?:and|forall\s*\([^()]*\))\s*\)|\(\s*:constraints\s*\)", re.IGNORECASE)
        joined = "".join(out)
        body, removed = joined[inside[0] : inside[1] + 1], 1
        while removed:  # one pass per level of nesting, every empty form of the level at once
            body, removed = empty.subn(lambda m: re.sub(r"[^\n]", " ", m.group(0)), body)
        out = list(joined[: inside[0]] + body + joined[inside[1] + 1 :])
    line, column = _position(text, found[0])
    warn(
        f"{name}:{line}:{column}: {len(found)} preference{'s' if len(found) != 1 else ''} ignored: vslsp plans for "
        "the hard goal and constraints only (soft goals and their :metric are left out)"
    )
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
    body = code[match.end() : _closing(code, match.start())]
    depth, tops = 0, 0
    for char in body:
        if char == "(":
            tops += depth == 0
            depth += 1
        elif char == ")":
            depth -= 1
    if tops > 1:
        line, column = _position(text, match.start())
        warn(
            f"{name}:{line}:{column}: (:constraints ...) lists {tops} constraints without (and ...); read as their "
            "conjunction (VAL drops such constraints)"
        )


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
    (
        re.compile(r"The expression '([^']+)' is not well-formed"),
        "type error in {0}: an argument's type does not match the predicate's parameter type",
    ),
    (re.compile(r"Type (\S+) is declared more than once"), "type '{0}' is declared more than once"),
    (re.compile(r"Missing goal section"), "the problem has no (:goal ...) section"),
    (
        re.compile(r"Name (\S+) already defined"),
        "the name '{0}' is given to two things (objects, types, predicates, actions); give each its own name",
    ),
    (re.compile(r"ExpressionManager\.(\w+)\(\) missing"), "'{0}' is missing an argument"),
    (re.compile(r"ExpressionManager\.(\w+)\(\) takes"), "'{0}' has too many arguments"),
)


def _operator(up_name: str) -> str:
    """unified-planning's name of an operator as PDDL writes it: ``SometimeBefore`` -> ``sometime-before``."""
    return re.sub(r"(?<!^)([A-Z])", r"-\1", up_name).lower()


def located_error(error: Exception, text: str, name: str) -> InputError:
    """An InputError ``NAME:LINE:COL: what`` from an exception raised by unified-planning's reader."""
    message = str(error)
    line, column = getattr(error, "lineno", None), getattr(error, "col", None)
    if type(error).__name__ in ("ParseException", "ParseSyntaxException"):
        found = re.sub(r"\s*\(at char \d+\), \(line:\d+, col:\d+\)", "", getattr(error, "msg", message))
        what = f"syntax error: {found}"
        section = re.match(r"\(:[\w-]+", text[getattr(error, "loc", 0) :])
        if section:
            kind = "problem" if re.search(r"\(\s*problem", text, re.IGNORECASE) else "domain"
            what = f"{what}: '{section.group(0)}' is not allowed here; sections come in the order {_ORDER[kind]}"
    else:
        place = _PLACE.search(message)
        if place:
            line, column = int(place.group(1)), int(place.group(2))
        what = message.splitlines()[0].strip() if message else type(error).__name__
        if isinstance(error, KeyError) and error.args:  # the reader's lookup of a name never declared
            key = str(error.args[0])
            kind = "type" if re.search(rf"-\s*{re.escape(key)}(?![\w-])", _code(text), re.IGNORECASE) else "name"
            what = f"undefined {kind} '{key}'"
        for pattern, template in _REWRITES:
            match = pattern.search(message)
            if match:
                groups = [_operator(g) if "ExpressionManager" in message else g for g in match.groups()]
                what = template.format(*groups)
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
