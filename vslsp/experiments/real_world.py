"""The five real-world VSL tasks of the paper ("Real-world Experiments", Table 1) in the
tabletop world, each a registered :class:`~vslsp.experiments.tabletop.TabletopExperiment` (its
layout, the tutor's moves and its reproduction protocol; the judge and the robot's operation are
in :mod:`vslsp.experiments.tabletop_protocol`).

- ``alphabet-ordering``: letters A-D put in a row by a static right-angle baseline (relative and
  absolute positioning); reproduced in order from a new scatter.
- ``animal-puzzle``: the frog's halves put on the 'pond' label, the giraffe's on the 'tree';
  the labels are moved before the reproduction (relative positioning).
- ``tower-of-hanoi``: three disks moved from the first base to the second in seven moves
  (several operations on one object, stacking). With the user's intervention (``--intervention``:
  by default on odd seeds, :class:`Intervention`) the tutor makes the first move to the third
  base; the robot watches, recognises the moved disk as operation 1's
  (:func:`~vslsp.vsl.reproduction.identify_moved`), and goes on with operation 2. Nothing else
  changes: each pre-place observation is matched against the scene as it now is, and since the
  bases look alike only what lies on and around them decides, the moves follow the tutor's
  choice and the tower ends on the third base.
- ``animals-vs-machines``: the tutor puts two animal and two machine cards into their bins; in
  the reproduction the tutor presents the cards one at a time in a new order, and the robot
  searches the whole pre-pick dictionary for the best match
  (:func:`~vslsp.vsl.reproduction.identify`) instead of following the sequence (classification).
- ``domino``: five picture-domino pieces laid end to end; in the reproduction the tutor opens
  with the first or the second piece anywhere (turned a little), and the tutor and the robot
  take turns: the robot recognises the piece the tutor laid and answers with the next one.

"""

from __future__ import annotations

import copy
import enum
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from vslsp.errors import InputError
from vslsp.experiments.tabletop import TabletopExperiment
from vslsp.experiments.tabletop_protocol import (
    OperationOutcome,
    judge_relation,
    look,
    placement_like,
    robot_operation,
    tutor_operation,
)
from vslsp.outcomes import Diagnosis
from vslsp.tasks.base import Option, TrialResult
from vslsp.vision.features import Features, extract_features
from vslsp.vision.matching import NoMatch
from vslsp.vsl.reproduction import find_place, identify, identify_moved, match_object
from vslsp.worlds.panda_table import Placement
from vslsp.worlds.panda_table import layouts as scenes

if TYPE_CHECKING:
    from vslsp.vision.matching import Match
    from vslsp.vsl.pick_place import PickPlaceDemonstration


class AlphabetOrdering(TabletopExperiment):
    name = "alphabet-ordering"
    description = "Letters A-D put in a row by a static right-angle baseline (relative and absolute positioning)."

    def layout(self, rng, phase):
        letters = scenes.letters()
        keep_out = [(x, y, 0.05) for x, y, _ in scenes.LETTER_GOALS.values()]
        keep_out += [(x, 0.1825, 0.02) for x in (0.47, 0.51, 0.55)]  # the baseline's short arm
        return scenes.baseline_arms() + list(zip(letters, scenes.scatter(rng, letters, keep_out)))

    def moves(self, rng):
        for letter, (x, y, yaw) in scenes.LETTER_GOALS.items():
            jitter = rng.normal(0.0, 0.002, 2)
            yield letter, (lambda world, p=Placement(x + jitter[0], y + jitter[1], yaw): p), "baseline-long"


class AnimalPuzzle(TabletopExperiment):
    name = "animal-puzzle"
    description = "The frog's halves put on the 'pond' label, the giraffe's on the 'tree'; the labels move."

    def layout(self, rng, phase):
        labels = scenes.labels()
        if phase == "demonstration":
            poses = [(0.61, 0.13, 0.0), (0.61, -0.13, 0.0)]
        else:  # the tutor moves the labels before the reproduction
            region = ((0.57, 0.64), (-0.22, 0.22))
            poses = [(p.x, p.y, rng.uniform(-0.5, 0.5)) for p in scenes.scatter(rng, labels, region=region)]
        pieces = scenes.puzzle_pieces()
        taken = [scenes.disc(label, pose) for label, pose in zip(labels, poses)]
        return [(label, Placement(*pose)) for label, pose in zip(labels, poses)] + list(
            zip(pieces, scenes.scatter(rng, pieces, taken))
        )

    def moves(self, rng):
        for animal in ("frog", "giraffe"):
            label = scenes.LABEL_OF[animal]
            for part in (0, 1):
                local = scenes.ON_LABEL[part]

                def where(world, label=label, local=local):
                    x, y, _, yaw = world.truth(label)
                    return Placement(*scenes.compose((x, y, yaw), local), on=label)

                yield f"{animal}-{part}", where, label


class Intervention(enum.StrEnum):
    """Whether the user intervenes in a tower-of-hanoi trial (``--intervention``)."""

    BY_SEED = "by-seed"  # the paper's protocol: the user makes the first move on odd seeds only
    NONE = "none"  # never: the robot makes all seven moves
    FIRST_MOVE = "first-move"  # always: the user makes the first move to the third base


class TowerOfHanoi(TabletopExperiment):
    name = "tower-of-hanoi"
    description = (
        "Three disks moved in seven moves (stacking); on odd seeds the user makes the first move and the "
        "robot goes on from there."
    )
    options = TabletopExperiment.options | {Option.INTERVENTION}

    intervention = False  # the user makes the first move in this trial

    @property
    def intervention_choice(self) -> Intervention:
        """The ``--intervention`` option (:attr:`Intervention.BY_SEED` when not given)."""
        return Intervention(self.option(Option.INTERVENTION, Intervention.BY_SEED))

    def check(self) -> None:
        given = self.option(Option.INTERVENTION, Intervention.BY_SEED)
        if given not in set(Intervention):
            raise InputError(
                f"--intervention takes {', '.join(Intervention)} (the user makes the first move on odd seeds, "
                f"never, or always), got {given!r}"
            )
        super().check()

    def for_seed(self, seed: int) -> TowerOfHanoi:
        """With the user's intervention in the trial of ``seed`` (by default: odd seeds), the user makes
        the first move to the third base."""
        chosen = self.intervention_choice
        if chosen is Intervention.NONE or (chosen is Intervention.BY_SEED and seed % 2 == 0):
            return self
        trial = copy.copy(self)
        trial.intervention, trial.variant = True, "intervention"
        trial.anchor_map = {"base-2": "base-3", "base-3": "base-2"}
        return trial

    def layout(self, rng, phase):
        layout = scenes.hanoi_bases()
        below = "base-1"
        x, y, _ = scenes.BASE_POSES[1]
        for disk in reversed(scenes.hanoi_disks()):
            offset = rng.normal(0.0, 0.002, 2)
            layout.append((disk, Placement(x + offset[0], y + offset[1], rng.uniform(-0.3, 0.3), on=below)))
            below = disk.name
        return layout

    def moves(self, rng):
        stacks = {1: ["disk-3", "disk-2", "disk-1"], 2: [], 3: []}
        for disk, target in scenes.hanoi_moves():
            name = f"disk-{disk}"
            source = next(b for b, stack in stacks.items() if stack and stack[-1] == name)
            stacks[source].pop()
            below = stacks[target][-1] if stacks[target] else f"base-{target}"
            stacks[target].append(name)
            jitter = rng.normal(0.0, 0.002, 2)

            def where(world, target=target, below=below, jitter=jitter):
                x, y, _ = scenes.BASE_POSES[target]
                return world.as_it_lies(Placement(x + jitter[0], y + jitter[1], 0.0, on=below))

            yield name, where, below  # judged on what it stands on: stack order

    def reproduce(self, world, demo, rng, keep=False):
        if not self.intervention:
            return super().reproduce(world, demo, rng, keep)
        # The user makes the first move to the third base; the robot watches and carries on.
        before = look(world)
        x, y, _ = scenes.BASE_POSES[3]
        outcomes = [tutor_operation(world, demo, 0, self.anchor_map, Placement(x, y, 0.0, on="base-3"))]
        after = look(world)
        seen = identify_moved(demo.demonstration, before, after, list(range(len(demo.items))))
        start = 1 if seen == 0 else 0  # had the robot not recognised the tutor's move, it would redo it
        outcomes += [
            robot_operation(world, demo, k, self.anchor_map, after if k == start else None, keep=keep)
            for k in range(start, len(demo.items))
        ]
        return outcomes

    def summary(self, results: list[TrialResult]) -> dict:
        """The tabletop summary; a run given ``--intervention`` records it as ``intervention_choice``
        (the studio re-runs a trial with it; ``intervention`` is the tally of the trials with one)."""
        data = super().summary(results)
        if Option.INTERVENTION in self.settings:
            data["intervention_choice"] = str(self.intervention_choice)
        return data

    def markdown(self, data: Mapping[str, Any]) -> list[str]:
        lines = super().markdown(data)
        if "intervention" in data:
            when = "every trial" if data.get("intervention_choice") == Intervention.FIRST_MOVE else "odd seeds"
            lines += [
                f"User intervention ({when}): {data['intervention']['successes']}/"
                f"{data['intervention']['trials']} trials reached the tower on the third base.",
                "",
            ]
        return lines


class AnimalsVsMachines(TabletopExperiment):
    name = "animals-vs-machines"
    description = "Cards presented one at a time, each put in its bin (classification by the best match)."

    def layout(self, rng, phase):
        cards = scenes.pictures()
        if phase == "demonstration":
            region = ((0.33, 0.45), scenes.SCATTER_Y)
            return scenes.bins() + list(zip(cards, scenes.scatter(rng, cards, region=region)))
        return scenes.bins() + [(card, scenes.hold_placement(k + 2)) for k, card in enumerate(cards)]

    def moves(self, rng):
        filled = {"animals": 0, "machines": 0}
        for k in rng.permutation(len(scenes.SUBJECTS)):
            subject = scenes.SUBJECTS[k]
            kind = "animals" if scenes.textures.PICTURES[subject] == "animal" else "machines"
            slot = scenes.BIN_SLOTS[filled[kind]]
            filled[kind] += 1
            yield (
                subject,
                (
                    lambda world, b=f"bin-{kind}", s=slot: Placement(
                        *scenes.compose(world.truth(b)[:2] + (world.truth(b)[3],), s), on=b
                    )
                ),
                f"bin-{kind}",
            )

    def reproduce(self, world, demo, rng, keep=False):
        order = list(demo.items)
        while order == list(demo.items):  # a new order
            order = [demo.items[k] for k in rng.permutation(len(order))]
        outcomes, remaining = [], list(range(len(order)))
        for subject in order:
            (shown,) = scenes.scatter(rng, [world.specs[subject]], region=((0.34, 0.45), (-0.2, 0.2)))
            world.tutor_move(subject, shown)
            image = look(world)
            found = identify(demo.demonstration, image, extract_features(image), remaining)
            expected = demo.items.index(subject)
            if found is None:
                outcomes.append(OperationOutcome(expected, "robot", subject, Diagnosis.NO_MATCH))
                continue
            k, match = found
            remaining.remove(k)
            outcome = robot_operation(world, demo, k, self.anchor_map, image, match, keep)
            if k != expected:  # the robot took the card for another: judge where the shown card went
                outcome = OperationOutcome(
                    expected,
                    "robot",
                    subject,
                    Diagnosis.WRONG_OBJECT,
                    outcome.planned,
                    outcome.result,
                    judge_relation(world, demo, expected, {})[1],
                    outcome.observation,
                )
            outcomes.append(outcome)
        return outcomes


class Domino(TabletopExperiment):
    name = "domino"
    description = "Five picture-domino pieces laid end to end, the tutor and the robot taking turns."

    def layout(self, rng, phase):
        pieces = scenes.domino_pieces()
        return list(zip(pieces, scenes.scatter(rng, pieces)))

    def moves(self, rng):
        start = Placement(*scenes.DOMINO_START)
        yield "domino-1", (lambda world: start), None
        for k in range(2, scenes.DOMINOES + 1):
            previous = f"domino-{k - 1}"
            yield (
                f"domino-{k}",
                (
                    lambda world, p=previous: Placement(
                        *scenes.compose(world.truth(p)[:2] + (world.truth(p)[3],), scenes.DOMINO_NEXT)
                    )
                ),
                previous,
            )

    def owed(self, demo, outcomes):
        """The game goes on from the tutor's opening piece to the last one."""
        return list(range(outcomes[0].index + 1, len(demo.items))) if outcomes else []

    def reproduce(self, world, demo, rng, keep=False):
        first = int(rng.integers(0, 2))  # the tutor opens with the first piece or the second
        opening = _domino_opening(rng, scenes.DOMINOES - first)
        outcomes: list[OperationOutcome] = []
        k, where = first, Placement(*opening)
        while k < len(demo.items):
            before = look(world)
            laid = {o.index for o in outcomes}
            outcomes.append(tutor_operation(world, demo, k, self.anchor_map, where, judged=k != first))
            after = look(world)
            seen = identify_moved(
                demo.demonstration, before, after, [j for j in range(len(demo.items)) if j not in laid]
            )
            if seen is None or seen + 1 >= len(demo.items) or seen + 1 in laid:
                break
            features = extract_features(after)
            place = answer_place(demo.demonstration, seen, seen + 1, after, features)
            outcomes.append(
                robot_operation(
                    world, demo, seen + 1, self.anchor_map, after, keep=keep, place_match=place, features=features
                )
            )
            k = seen + 2
            if k < len(demo.items):
                where = placement_like(world, demo, k, demo.anchors[k])
        return outcomes


def answer_place(
    demo: PickPlaceDemonstration, played: int, answer: int, world: np.ndarray, features: Features
) -> Match | None:
    """Turn-taking: where operation ``answer`` puts its piece, searched only about the piece of
    operation ``played`` that the tutor just laid (found by its features φ in ``world``), within
    the demonstrated distance between their places and a pre-place frame more. The pre-place
    frame, grown while ambiguous, also holds pieces laid before in the demonstration; in a new
    game they lie elsewhere and would draw the match to them. None when the played piece is not
    found or nothing matches about it (the robot then searches the whole view). ``features``
    are the SIFT features of ``world``."""
    piece = match_object(demo, played, world, features)
    if isinstance(piece, NoMatch):
        return None
    reach = float(np.hypot(*np.subtract(demo.operations[answer].place_point, demo.operations[played].place_point)))
    half = reach + demo.pick_frame
    near = np.all(np.abs(features.keypoints[:, :2] - (piece.x, piece.y)) <= half, axis=1)
    place = find_place(demo, answer, world, Features(features.keypoints[near], features.descriptors[near]))
    return None if isinstance(place, NoMatch) else place


def _domino_opening(rng: np.random.Generator, pieces: int) -> tuple[float, float, float]:
    """Where the tutor lays the opening piece: anywhere in the far band, turned a little, so
    that the ``pieces`` still to come fit in the workspace."""

    for _ in range(1000):
        x, yaw = rng.uniform(0.62, 0.66), -np.pi / 2.0 + rng.uniform(-0.12, 0.12)
        length = (pieces - 1) * scenes.DOMINO_NEXT[0]
        y = rng.uniform(-0.26 + length * abs(np.sin(yaw)), 0.26)
        end = scenes.compose((x, y, yaw), (length, 0.0, 0.0))
        if 0.6 <= end[0] <= 0.68 and -0.27 <= end[1]:
            return float(x), float(y), float(yaw)
    raise RuntimeError("no opening for the domino chain")  # a layout bug, not input
