"""Shared inputs of the symbolic tests: the shipped PDDL files and the paper's demonstrations,
written as the grounding stage records them (object -> {"far": bool} before and after)."""

from pathlib import Path

from vslsp.symbolic import Atom, Step

PDDL = Path(__file__).resolve().parents[2] / "pddl"


def scene(**far: bool) -> dict[str, dict[str, bool]]:
    """``scene(green=True, red=False)`` -> ``{"green": {"far": True}, "red": {"far": False}}``."""
    return {colour: {"far": value} for colour, value in far.items()}


def step(action: str | None, obj: str, before: dict, **changes: bool) -> Step:
    """The step acting on ``obj`` in ``before``; ``changes`` give the post-action values."""
    after = {o: dict(v) for o, v in before.items()}
    for colour, value in changes.items():
        after[colour]["far"] = value
    return Step(action, obj, before, after)


def demonstration(start: dict, *operations: tuple[str, str]) -> list[Step]:
    """Consecutive steps from ``start``: ``("pull", "green")`` makes green near, push far."""
    steps, state = [], {o: dict(v) for o, v in start.items()}
    for action, obj in operations:
        steps.append(step(action, obj, state, **{obj: action == "push"}))
        state = {o: dict(v) for o, v in steps[-1].after.items()}
    return steps


def far(obj: str) -> Atom:
    """The ground atom ``(far obj)``."""
    return Atom("far", (obj,))
