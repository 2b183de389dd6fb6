"""What the author page draws on its editors: diagnostics as marks and line decorations, hover titles,
completion at the cursor (the language server's context: :mod:`vslsp.lsp.context`), the lines of the
problem's constraints and goal (for violations and conflicts), all from the language engine's spans."""

from __future__ import annotations

from typing import Any

#: Completion's wants that name a kind of the index.
_KINDS = {"type": ("type",), "action": ("action",), "predicate": ("predicate",)}


def line_starts(text: str) -> list[int]:
    """The offset of each line's first character (index 0 is line 1)."""
    starts = [0]
    for number, character in enumerate(text):
        if character == "\n":
            starts.append(number + 1)
    return starts


def offset(starts: list[int], text: str, line: int, column: int) -> int:
    """The character offset of 1-based ``line``/``column`` in ``text`` (clamped to the text)."""
    line = max(1, min(line, len(starts)))
    return max(0, min(starts[line - 1] + column - 1, len(text)))


def decorations(text: str, file: str, checked: dict) -> tuple[list[dict], dict[int, str]]:
    """CodeMirror decorations (diagnostic marks and lines, the message at the line's end, hover titles)
    and line tooltips for ``file``'s diagnostics in a :func:`vslsp.studio.pddl.check` answer."""
    starts = line_starts(text)
    found: list[dict] = []
    tooltips: dict[int, str] = {}
    for hover in checked.get("hovers", {}).get(file, []):
        begin = offset(starts, text, hover["line"], hover["column"])
        end = offset(starts, text, hover["line"], hover["end_column"])
        if end > begin:
            found.append(
                {
                    "kind": "mark",
                    "from": begin,
                    "to": end,
                    "class": "vslsp-ref",
                    "attributes": {"data-hover": hover["text"]},  # the editor's styled hover tooltip shows it
                }
            )
    lines_done: set[int] = set()
    for diagnostic in checked.get("diagnostics", []):
        if diagnostic["file"] != file:
            continue
        severity = diagnostic["severity"]
        line = max(1, min(diagnostic["line"], len(starts)))
        begin = offset(starts, text, line, diagnostic["column"])
        end = offset(starts, text, diagnostic.get("end_line", line), diagnostic.get("end_column", 0))
        if end > begin:
            found.append({"kind": "mark", "from": begin, "to": end, "class": f"vslsp-{severity}"})
        tooltips[line] = (tooltips[line] + "\n" if line in tooltips else "") + diagnostic["message"]
        if line not in lines_done:
            lines_done.add(line)
            found.append({"kind": "line", "line": line, "class": f"vslsp-line-{severity}"})
            line_end = starts[line] - 1 if line < len(starts) else len(text)
            found.append(
                {
                    "kind": "widget",
                    "position": line_end,
                    "text": f"  {diagnostic['message']}",
                    "class": f"vslsp-say-{severity}",
                }
            )
    return found, tooltips


#: CodeMirror's completion types (its icons) of the kinds of name PDDL completes.
COMPLETION_TYPES = {
    "predicate": "function",
    "action": "method",
    "type": "type",
    "constant": "constant",
    "object": "constant",
    "variable": "variable",
    "keyword": "keyword",
}


def complete(text: str, at: int, checked: dict, problem: bool) -> dict:
    """Completion at offset ``at``: ``{"from": the start of the name typed, "items": [names], "entries":
    [{"label", "kind" (predicate, type, constant, object, variable, keyword), "type" (CodeMirror's icon),
    "detail" (the declaration: ``(far ?b - block)``)}]}``."""
    from vslsp.lsp import context
    from vslsp.symbolic.language import EFFECT_OPERATORS, GOAL_OPERATORS, PDDL3_NAMES, REQUIREMENTS
    from vslsp.symbolic.language.vocabulary import ACTION_KEYWORDS, DOMAIN_SECTIONS, PROBLEM_SECTIONS

    cursor = context.cursor_at(text, at)
    names = checked.get("names", {})
    want = cursor.want
    items: list[str] = []
    if want == context.PREDICATE:
        operators = {"goal": GOAL_OPERATORS, "effect": EFFECT_OPERATORS, "constraints": (*PDDL3_NAMES, *GOAL_OPERATORS)}
        items = [*names.get("predicate", []), *operators.get(cursor.formula, ())]
    elif want == context.TYPE:
        items = [*names.get("type", []), "object"]
    elif want == context.REQUIREMENT:
        items = list(REQUIREMENTS)
    elif want == context.SECTION:
        items = list(PROBLEM_SECTIONS if problem else DOMAIN_SECTIONS)
    elif want == context.ACTION_KEYWORD:
        items = list(ACTION_KEYWORDS)
    elif want == context.ARGUMENT:
        items = [*names.get("constant", []), *(names.get("object", []) if problem else [])]
        if not problem or cursor.prefix.startswith("?"):
            items += _variables(text)
    prefix = cursor.prefix.lower()
    chosen = [item for item in dict.fromkeys(items) if item.lower().startswith(prefix)][:50]
    return {"from": cursor.start, "items": chosen, "entries": [_entry(item, names, checked) for item in chosen]}


def _entry(item: str, names: dict, checked: dict) -> dict:
    signatures = checked.get("signatures", {})
    kind = next(
        (k for k in ("predicate", "type", "constant", "object") if item in names.get(k, ())),
        "variable" if item.startswith("?") else "type" if item == "object" else "keyword",
    )
    detail = signatures.get(kind, {}).get(item, "")
    return {"label": item, "kind": kind, "type": COMPLETION_TYPES[kind], "detail": detail or kind}


def _variables(text: str) -> list[str]:
    import re

    return sorted(set(re.findall(r"\?[A-Za-z][\w-]*", text)))


def formula_lines(problem_text: str, problem_file: str) -> dict[str, Any]:
    """The lines of the problem's constraints (in order) and of its goal, for marking violations."""
    from vslsp.symbolic.language import analyse, text_of

    analysis = analyse(problem_text, problem_file)
    sections = analysis.sections(problem_file)
    listed: list[Any] = []
    constraints = sections.get(":constraints")
    if constraints is not None:
        listed = list(constraints.items[1:])
        if len(listed) == 1 and not isinstance(listed[0], str) and getattr(listed[0], "key", "") == "and":
            listed = list(listed[0].items[1:])
    goal = sections.get(":goal")
    return {
        "constraints": [
            {"text": text_of(item, lower=True), "line": item.span.line} for item in listed if hasattr(item, "span")
        ],
        "goal": goal.span.line if goal is not None else None,
    }
