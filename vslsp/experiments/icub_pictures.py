"""The pull-in-order experiment through picture files, as a user with a camera over a line on a
table would run VSL-SP (docs/recordings.md, "A PDDL domain from pictures"): the trial's own
exploration (the robot tries push and pull) and the tutor's demonstration, rendered by the
experiment's steps (:func:`~vslsp.experiments.icub_scripts.explore`,
:func:`~vslsp.experiments.icub_scripts.watch`) on its seed, saved as ``explore/NN-pre.png``,
``explore/NN-post.png``, ``NN-pre.png``, ``NN-post.png`` with ``names.json``; and what the
experiment itself learns from them, to compare ``vslsp learn-domain`` against."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from vslsp.experiments.icub_run import IcubRun
from vslsp.experiments.icub_scripts import ORDERED_COLOURS, explore, watch
from vslsp.outputs import write_text
from vslsp.skills.library import SkillLibrary
from vslsp.symbolic import Domain, Problem, learn_task, make_problem
from vslsp.vision.image import write_image
from vslsp.worlds.icub import line_layout


@dataclass(frozen=True)
class ExperimentLearned:
    """What the pull-in-order trial of a seed learns: its action models and its problem in the
    demonstration's scene."""

    domain: Domain
    problem: Problem


def write_pull_in_order(seed: int, folder: str | Path, library: SkillLibrary) -> ExperimentLearned:
    """Render the trial of ``seed`` into the picture folder ``folder`` (created) and return what
    the experiment learns from the same observations."""
    folder = Path(folder)
    trial = IcubRun(seed)
    rng = np.random.default_rng(seed)  # the experiment's: without faults nothing is drawn before play
    domain = explore(trial, rng, library)
    explored = list(trial.observations)
    with trial.world(line_layout(seed, ORDERED_COLOURS, (True,) * len(ORDERED_COLOURS))) as world:
        steps = watch(world, trial, [(c, "pull") for c in ORDERED_COLOURS], "demonstration")
    demonstrated = trial.observations[len(explored) :]
    _write_pairs(folder / "explore", [(pre, post, f"{g.action} {g.name}") for _, pre, post, g, _ in explored])
    _write_pairs(folder, [(pre, post, f"pull {s.obj}") for (_, pre, post, _, _), s in zip(demonstrated, steps)])
    task = learn_task([steps], ordered=True)
    initial = {obj: dict(values) for obj, values in steps[0].before.items()}
    return ExperimentLearned(domain, make_problem(domain, task, initial))


def _write_pairs(folder: Path, pairs: list[tuple[np.ndarray, np.ndarray, str]]) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    names = {}
    for k, (pre, post, name) in enumerate(pairs, start=1):
        write_image(folder / f"{k:02d}-pre.png", pre)
        write_image(folder / f"{k:02d}-post.png", post)
        names[f"{k:02d}"] = name
    write_text(folder / "names.json", json.dumps(names, indent=2) + "\n")
