"""VSL-SP from a user's own pictures (docs/recordings.md, "A PDDL domain from pictures"): the
paper's learning of action models from pre-/post-action observations (Table 3) and of the task
and its order from one demonstration ("Pull All Objects in a Given Order"), on a folder of image
pairs instead of the simulator.

Per operation i (numbered 1, 2, ... without gaps): ``i-pre.png`` and ``i-post.png`` (PNG or
JPEG), and ``names.json`` mapping each number to the operation's action and object
(``{"01": "pull red", "02": "push blue"}``). The demonstration's order is the goal's order. An
optional subfolder ``explore/`` of the same form holds the robot's own executions of its skills;
the action models are learned from them as the iCub experiments learn them, and from the
demonstration's pairs when there is no ``explore/``.

Each pair is grounded as ``vslsp ground`` grounds it (:func:`vslsp.grounding.ground`, every
object's literals by :func:`vslsp.grounding.ground_scene`) into a :class:`~vslsp.symbolic.Step`;
:func:`vslsp.symbolic.learn_domain`, :func:`~vslsp.symbolic.learn_task` and
:func:`~vslsp.symbolic.make_problem` do the rest, as in :mod:`vslsp.experiments.icub_scripts`.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from vslsp.errors import InputError, VslspError
from vslsp.files import read_json, shown
from vslsp.folders import MAX_SIDE_FILE_BYTES, Form, operation_files, spelled_number
from vslsp.grounding import Grounding, Predicate, ground, ground_scene
from vslsp.loop.pipeline import scene_literals
from vslsp.symbolic import Domain, LearnedTask, Problem, Step, learn_domain, learn_task, make_problem
from vslsp.vision.change import default_min_move
from vslsp.vision.image import IMAGE_EXTENSIONS, MAX_FOLDER_PIXELS, read_pictures

#: The actions of VSL-SP's skills: what a demonstrated operation may be named.
ACTIONS = ("push", "pull")
EXPLORE = "explore"


@dataclass(frozen=True, eq=False)
class PicturePair:
    """One operation's pictures: its number as the files spell it (``"01"``), the action and
    object ``names.json`` gives it, the files and their RGB images (H, W, 3) uint8."""

    number: str
    action: str
    obj: str
    pre_file: Path
    post_file: Path
    pre: np.ndarray
    post: np.ndarray


@dataclass(frozen=True, eq=False)
class PictureFolder:
    """A folder read and checked: the demonstration's pairs in order and the robot's own
    executions (``explore/``; empty when there is none)."""

    folder: Path
    demonstration: tuple[PicturePair, ...]
    explorations: tuple[PicturePair, ...]


@dataclass(frozen=True, eq=False)
class LearnedOperation:
    """A pair grounded: its :class:`Grounding` and the :class:`Step` learned from."""

    pair: PicturePair
    grounding: Grounding
    step: Step


@dataclass(frozen=True, eq=False)
class LearnedDomain:
    """What the folder taught: the action models, the task, the problem in the demonstration's
    first scene, and every operation grounded."""

    domain: Domain
    task: LearnedTask
    problem: Problem
    demonstration: tuple[LearnedOperation, ...]
    explorations: tuple[LearnedOperation, ...]


FORM = Form(
    re.compile(r"^(\d{1,4})-(pre|post)(\.png|\.jpg|\.jpeg)$", re.IGNORECASE),
    IMAGE_EXTENSIONS,
    {"pre": "pre-action picture", "post": "post-action picture"},
    (),
    "NN-pre or NN-post (.png or .jpg)",
    "picture",
    "01-pre.png, 01-post.png",
    "the operations' pictures",
)


def read_picture_folder(folder: str | Path, max_pixels: int = MAX_FOLDER_PIXELS) -> PictureFolder:
    """Read and check ``folder`` (the module's docstring) before any work. Raises InputError
    naming the file: a missing or unreadable picture, a name out of the form, numbers with
    gaps, pictures of different sizes or of more than ``max_pixels`` together, a ``names.json``
    missing, not parsing, naming an unknown action or leaving out an operation."""
    folder = Path(folder)
    demonstration = _pair_files(folder)
    explore = folder / EXPLORE
    explorations = _pair_files(explore) if explore.is_dir() else []
    pictures = iter(read_pictures([f for _, files in demonstration + explorations for f in files], max_pixels))
    pairs = [
        PicturePair(spelled_number(pre), *name, pre, post, next(pictures), next(pictures))
        for name, (pre, post) in demonstration + explorations
    ]
    return PictureFolder(folder, tuple(pairs[: len(demonstration)]), tuple(pairs[len(demonstration) :]))


def _pair_files(folder: Path) -> list[tuple[tuple[str, str], tuple[Path, Path]]]:
    """Per operation of ``folder`` in order: its (action, object) and its (pre, post) files."""
    found = operation_files(folder, FORM)
    names = _names(folder / "names.json", {n: spelled_number(roles["pre"]) for n, roles in found.items()})
    return [(names[n], (found[n]["pre"], found[n]["post"])) for n in sorted(found)]


def _names(path: Path, spelled: dict[int, str]) -> dict[int, tuple[str, str]]:
    """Operation number -> (action, object) from ``names.json``."""
    example = '{"01": "pull red", "02": "push blue"}'
    if not path.exists():
        raise InputError(f"{shown(path)} is missing: name each operation's action and object, e.g. {example}")
    data = read_json(path, "names", MAX_SIDE_FILE_BYTES)
    if not isinstance(data, dict):
        raise InputError(
            f"{shown(path)}: give an object mapping each operation's number to its action and object, e.g. {example}"
        )
    names: dict[int, tuple[str, str]] = {}
    for key, value in data.items():
        if not (isinstance(key, str) and key.isdigit() and int(key) in spelled):
            raise InputError(
                f"{shown(path)}: {key!r} is no operation of the folder (operations: {', '.join(spelled.values())})"
            )
        words = value.split() if isinstance(value, str) else []
        if len(words) != 2:
            raise InputError(
                f'{shown(path)}: operation {key} is {value!r}; give its action and object, e.g. "pull red"'
            )
        if words[0] not in ACTIONS:
            raise InputError(
                f"{shown(path)}: operation {key} names the action {words[0]!r}, which VSL-SP has no skill for "
                f"(actions: {', '.join(ACTIONS)})"
            )
        names[int(key)] = (words[0], words[1])
    missing = [spelled[n] for n in sorted(spelled) if n not in names]
    if missing:
        raise InputError(f"{shown(path)}: operation {missing[0]} has no name; name every operation's action and object")
    return names


def ground_pair(pair: PicturePair, robot_side: str, predicates: Sequence[Predicate] | None) -> LearnedOperation:
    """Ground one pair as ``vslsp ground`` does and check it against its name. Raises InputError
    naming the files: nothing moved, several moved, another object moved than named, an action
    that contradicts what ``far`` saw, or none of the object's predicates changed."""
    files = f"{shown(pair.pre_file)} -> {shown(pair.post_file)}"
    try:
        grounding = ground(pair.pre, pair.post, robot_side, predicates, default_min_move(pair.pre.shape))
        before, after = ground_scene(pair.pre, robot_side), ground_scene(pair.post, robot_side)
    except VslspError as error:
        raise InputError(f"{files}: {error}") from None
    named = f"{pair.action} {pair.obj}"
    if grounding.name != pair.obj:
        raise InputError(f"{files}: {grounding.name} moved, but names.json says {named!r}")
    if grounding.action is not None and grounding.action != pair.action:
        raise InputError(
            f"{files}: {grounding.name} went from {_far(grounding.far_pre)} to {_far(grounding.far_post)} "
            f"(a {grounding.action}), but names.json says {named!r}"
        )
    step = Step(pair.action, grounding.name, scene_literals(before, predicates), scene_literals(after, predicates))
    if not step.changed():
        raise InputError(
            f"{files}: {grounding.name} moved but stayed {_far(grounding.far_pre)} and none of its predicates "
            "changed; a pair shows an operation that changes its object"
        )
    return LearnedOperation(pair, grounding, step)


def _far(value: bool) -> str:
    return "far" if value else "not far"


def learn_picture_domain(
    pictures: PictureFolder, robot_side: str = "bottom", predicates: Sequence[Predicate] | None = None
) -> LearnedDomain:
    """VSL-SP's learning on a read folder: the action models from ``explore/`` (else from the
    demonstration), the ordered task from the demonstration (its action's effects kept to what
    the models change when the user's ``predicates`` are grounded, as the experiments do), and
    the problem in the scene of the demonstration's first picture."""
    demonstration = tuple(ground_pair(p, robot_side, predicates) for p in pictures.demonstration)
    explorations = tuple(ground_pair(p, robot_side, predicates) for p in pictures.explorations)
    domain = learn_domain(op.step for op in (explorations or demonstration))
    task = learn_task([[op.step for op in demonstration]], ordered=True, models=domain if predicates else None)
    first = ground_scene(pictures.demonstration[0].pre, robot_side)
    problem = make_problem(domain, task, scene_literals(first, predicates))
    return LearnedDomain(domain, task, problem, demonstration, explorations)
