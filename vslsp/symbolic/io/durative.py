"""The learned domain with durations: each action written as a PDDL 2.1 durative action.

Paper: "Implementation" (the learned action models handed to a planner); issue 41 item 4 (a
domain PlanSys2 takes as it is: it plans with durative actions only). An action ``a`` with
precondition ``φ`` and effects ``e₁ … eₙ`` becomes ``(:durative-action a :duration (= ?duration
d_a) :condition (at start φ) :effect (and (at end e₁) … (at end eₙ)))``: the precondition is
checked when the skill starts and its effects hold when it ends, as a robot's push or pull does.
A conditional effect ``(when c e)`` reads its condition at the start: ``(when (at start c) (at
end e))``. The durations ``d_a`` (seconds) come from the skills' learned DMPs
(:func:`skill_durations`).
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping

from vslsp.errors import InputError
from vslsp.symbolic.model.domain import Action, Domain, When, _typed
from vslsp.symbolic.model.formula import And


def durative_domain_pddl(domain: Domain, durations: Mapping[str, float]) -> str:
    """The domain file of ``domain`` with every action durative, lasting ``durations[name]`` seconds
    (InputError naming an action without a positive, finite duration)."""
    text = domain.to_pddl()
    first = text.find("\n  (:action ")
    if first < 0:
        return text
    head = re.sub(
        r"\(:requirements([^()]*)\)",
        lambda m: f"(:requirements{m.group(1)} :durative-actions)",
        text[:first],
        count=1,
    )
    if "(:requirements" not in head:
        head = head.replace("\n", "\n  (:requirements :durative-actions)\n", 1)
    blocks = [durative_action_pddl(action, _duration(action.name, durations)) for action in domain.actions]
    return head + "\n" + "\n".join(blocks) + ")\n"


def durative_action_pddl(action: Action, duration: float) -> str:
    """``(:durative-action ...)`` of ``action``, lasting ``duration`` seconds."""
    lines = [
        f"  (:durative-action {action.name}",
        f"    :parameters ({_typed(action.parameters)})",
        f"    :duration (= ?duration {duration:.3f})",
    ]
    if action.precondition != And(()):
        lines.append(f"    :condition (at start {action.precondition.to_pddl()})")
    effects = " ".join(_timed_effect(e) for e in action.effects)
    lines.append(f"    :effect (and {effects})".replace("(and )", "(and)"))
    return "\n".join(lines) + ")"


def _timed_effect(effect: object) -> str:
    if isinstance(effect, When):
        return effect.to_pddl(timed=True)
    return f"(at end {effect.to_pddl()})"  # type: ignore[attr-defined]


def _duration(name: str, durations: Mapping[str, float]) -> float:
    value = durations.get(name)
    if value is None or not math.isfinite(value) or value <= 0:
        known = ", ".join(sorted(durations)) or "none"
        raise InputError(f"action {name} has no positive duration (skills with durations: {known}); teach its skill")
    return float(value)


def skill_durations(library: object) -> dict[str, float]:
    """Each skill's duration in seconds: ``2τ``, the reach DMP's rollout (τ the demonstrations' mean
    duration, :class:`vslsp.dmp.DMP`; twice τ lets the forcing term die out, as the skill executes it)."""
    skills = getattr(library, "skills", {})
    return {name: 2.0 * float(skill.reach.tau) for name, skill in dict(skills).items()}
