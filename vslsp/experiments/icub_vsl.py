"""VSL's own reproduction in the iCub experiments (paper, Algorithm 1 part II): each
demonstrated operation's object found in the current scene by match finding (SIFT + RANSAC,
adaptive frames, no PDDL) and brought to its demonstrated side of the line."""

from __future__ import annotations

import cv2
import numpy as np

from vslsp.errors import TaskFailed
from vslsp.experiments.icub_faults import Faults
from vslsp.experiments.icub_run import IcubRun
from vslsp.loop.monitor import execute_step
from vslsp.loop.perception import PerceivedState, perceive
from vslsp.skills.library import SkillLibrary
from vslsp.vision.features import FeatureMemo
from vslsp.vision.matching import Match
from vslsp.vision.objects import dark_mask
from vslsp.vsl.demonstration import Operation
from vslsp.vsl.matcher import Search, match_observation
from vslsp.worlds.icub import IcubLineWorld


def reproduce_vsl(
    world: IcubLineWorld, trial: IcubRun, library: SkillLibrary, demonstration, faults: Faults | None = None
) -> list[str]:
    """Reproduce a recorded demonstration by match finding: for each operation, find the
    demonstrated object in the current scene (SIFT + RANSAC, adaptive frame) and bring it to
    the demonstrated side of the line. A last look checks every object against its final
    demonstrated side and acts again on any that a later operation knocked back. Returns the
    objects acted on, in order. ``faults`` disturbs the steps it schedules (``--faults``)."""
    faults = faults or Faults()
    acted: list[str] = []
    memo = FeatureMemo()  # an unchanged world and a recorded observation seen again: SIFT once
    for op in demonstration.operations:
        _bring(world, trial, library, op, faults, acted, memo)
    last = {op.symbol: op for op in demonstration.operations}  # each object's final demonstrated side
    for op in demonstration.operations:
        if last[op.symbol] is op:
            _bring(world, trial, library, op, faults, acted, memo)
    return acted


def _bring(
    world: IcubLineWorld,
    trial: IcubRun,
    library: SkillLibrary,
    op: Operation,
    faults: Faults,
    acted: list[str],
    memo: FeatureMemo,
) -> None:
    """Bring the object of operation ``op`` to its demonstrated side (up to 3 attempts)."""
    for _ in range(3):
        state = perceive(world)
        found = _find_object(state, op, memo)
        target = op.grounding.far_post
        if found is None:
            raise TaskFailed(f"VSL finds no {op.symbol} object in the scene")
        name, how = found
        trial.details.setdefault("matched_by", []).append(how)
        if state.objects[name].far == target:
            return
        action = "push" if target else "pull"  # VSL's skills: push takes an object far, pull near
        shown = 1 + sum(title.startswith("VSL reproduction") for title, *_ in trial.observations)
        trial.say(f"VSL step {shown}: {action} {name} (found by {how})")
        index = faults.steps
        result, after = execute_step(world, library, action, name, state, target, faults.act)
        result = faults.mark(index, result)
        trial.steps.append(result)
        trial.show_step(world, f"VSL step {shown}: {action} {name}", result, faults.fault_of(index))
        # VSL's own steps, shown in the report (grounded only when drawn: a failed step may show no change)
        trial.observe(
            f"VSL reproduction step {shown}: {action} {name}", state.image, after.image, None, result, after.far()
        )
        if result.ok:
            acted.append(name)
            return
        trial.replans += 1
    raise TaskFailed(f"VSL could not bring {op.symbol} to the demonstrated side after 3 attempts")


def _find_object(state: PerceivedState, op: Operation, memo: FeatureMemo | None = None) -> tuple[str, str] | None:
    """The object of demonstrated operation ``op`` in the current scene, and how it was found.

    Match finding (:func:`~vslsp.vsl.matcher.match_observation`: SIFT + RANSAC with adaptive
    frames) of the recorded pre-action observation comes first, on both images without the
    landmark line (the line is no object, and where it crosses the frame its strong edges
    would align the line rather than the object's texture). The constraint it must fit: the
    placement lands on an object of the recorded symbol (its colour); one that does not is
    rejected and the search goes on without the features about it (the next best placement,
    up to :data:`_PLACEMENTS`). When none fits, the object's symbol decides.
    """
    observation, world = _without_landmark(op.pre_observation), _without_landmark(state.image)

    def fits(match: Match) -> bool:
        found = _object_at(state, match, op.object_size)
        return found is not None and found.split("_")[0] == op.symbol

    search = Search.growing(None, _PLACEMENTS, op.object_size)
    memo = memo or FeatureMemo()
    point = (op.pose_pre.x, op.pose_pre.y)
    match = match_observation(
        observation, world, point, op.object_size, search, memo(observation), memo(world), fits=fits
    )
    if isinstance(match, Match):
        name = _object_at(state, match, op.object_size)
        assert name is not None  # the match fits: an object lies under it
        return name, "match"
    if op.symbol in state.objects:
        return op.symbol, "symbol"
    return None


def _object_at(state: PerceivedState, match: Match, within: float) -> str | None:
    """The object nearest the match, when its centre is closer than ``within`` px."""
    best, distance = None, np.inf
    for name, obj in state.objects.items():
        d = float(np.hypot(obj.pixel[0] - match.x, obj.pixel[1] - match.y))
        if d < distance:
            best, distance = name, d
    return best if distance < within else None


_PLACEMENTS = 3  # placements tried before the symbol decides


def _without_landmark(image: np.ndarray) -> np.ndarray:
    """The image (H, W, 3) with the landmark's dark grey pixels painted in the table's colour
    (the image's median colour)."""
    dark = cv2.dilate(dark_mask(image), np.ones((3, 3), np.uint8)) > 0
    clean = image.copy()
    clean[dark] = np.median(image.reshape(-1, 3), axis=0).astype(np.uint8)
    return clean
