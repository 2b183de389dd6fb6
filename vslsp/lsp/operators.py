"""What a hover over a PDDL 3.0 trajectory-constraint operator says: its meaning on the plan's state
sequence (Gerevini & Long 2005, "Plan constraints and preferences in PDDL3"), and what vslsp's
planners do with it (docs/planning.md)."""

from __future__ import annotations

import re

from lsprotocol import types

_TIMED = "A timed constraint: vslsp's planners (no durations) refuse it."
MEANINGS = {
    "always": "`(always φ)`: φ holds in every state of the plan, the initial one included.",
    "sometime": "`(sometime φ)`: φ holds in at least one state of the plan.",
    "at-most-once": "`(at-most-once φ)`: φ becomes true at most once: once it has held and stopped "
    "holding, it never holds again.",
    "sometime-after": "`(sometime-after φ ψ)`: whenever φ holds, ψ holds then or in a later state.",
    "sometime-before": "`(sometime-before φ ψ)`: whenever φ holds, ψ has held in an earlier state "
    "(strictly before): φ only after ψ, the order a demonstration shows.",
    "at": "`(at end φ)`: φ holds in the final state (as a goal does).",
    "within": f"`(within t φ)`: φ holds at some time no later than t. {_TIMED}",
    "always-within": f"`(always-within t φ ψ)`: whenever φ holds, ψ holds within t. {_TIMED}",
    "hold-during": f"`(hold-during t1 t2 φ)`: φ holds from t1 to t2. {_TIMED}",
    "hold-after": f"`(hold-after t φ)`: φ holds after t. {_TIMED}",
    "preference": "`(preference name φ)`: a soft constraint. vslsp plans for the hard goal and "
    "constraints: preferences are removed, with a warning.",
}
_WORD = re.compile(r"[^\s();]+")


def operator_hover(text: str, position: types.Position, character: int) -> types.Hover | None:
    """The meaning of the PDDL 3.0 operator under the cursor (``character``: its column in characters),
    None elsewhere."""
    lines = text.split("\n")
    line = lines[position.line] if position.line < len(lines) else ""
    for match in _WORD.finditer(line):
        if match.start() <= character <= match.end():
            meaning = MEANINGS.get(match.group().lower())
            if meaning is None or line[: match.start()].rstrip()[-1:] != "(":
                return None  # only as the head of a list, not a name that happens to be spelt so
            return types.Hover(types.MarkupContent(types.MarkupKind.Markdown, meaning))
    return None
