"""VSL's match finding: Algorithm 1 part II, lines 13-14, ``findBestMatch(W_R, O_j, φ_j, C_j, L)``
with adaptive frames, written once for every task (the house-and-roof simulation, the Panda's
tabletop tasks, the iCub's VSL reproduction).

A recorded observation (pre-pick or pre-place) is found in the new world in two steps:

1. candidates: placements found one after the other by
   :func:`~vslsp.vision.matching.find_best_match` (SIFT, RANSAC copies, adaptive frames), each
   with the world features about the placements already found left out; a placement that does
   not fit the task's constraints (``fits``: C_j, e.g. the recorded symbol must be under it) is
   no candidate, and one within half an object of an earlier candidate is the same place;
2. disambiguation: with no comparison frames the first fitting placement is the match (its own
   frames grew while it was ambiguous); with comparison frames every candidate's colour
   correlation with the observation is measured as the frame grows, each frame ruling out for
   good the candidates it beats by :attr:`~vslsp.vision.parameters.FrameSearch.margin`, until one is left
   (the paper's adaptive frame telling identical objects apart by their surroundings, which
   "narrows down the possible matches"). Before a frame rules a candidate out, it is re-fitted
   (:func:`refit`) and compared again; the frame stops growing once its best correlation falls
   MARGIN below the best a smaller frame reached (it sees mostly what the two worlds do not
   share); and the match taken is re-fitted when its fit correlates poorly at the first
   frame: see :func:`match_observation`.

What differs between the tasks is data, a :class:`Search`: the rounds of placements (their
frame sides, how many, how far about each the world features are left out) and the comparison
frames.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import cv2
import numpy as np

from vslsp.stages import in_stage
from vslsp.vision.features import Features, extract_features
from vslsp.vision.image import as_rgb
from vslsp.vision.matching import Match, NoMatch, find_best_match
from vslsp.vision.parameters import DEFAULT_FRAME_SEARCH, FrameSearch
from vslsp.vision.transform import decompose


@dataclass(frozen=True)
class Round:
    """One round of the candidate search: up to ``tries`` placements, each found with frames of
    sides ``frames`` (px, growing; None: from the object's size to the whole world), the world
    features within ``leave_out`` px of each placement left out before the next one. Every
    round starts from all the world features."""

    frames: tuple[int, ...] | None
    tries: int = 1
    leave_out: float = 0.0


@dataclass(frozen=True)
class Search:
    """How a task finds a recorded observation: the ``rounds`` of placements, in order, and the
    frame sides (px, growing) at which the candidates are ``compare``-d (none: the first
    placement that fits is the match)."""

    rounds: tuple[Round, ...]
    compare: tuple[int, ...] = ()
    turns: int = 0

    @classmethod
    def growing(
        cls, frames: Sequence[int] | None = None, tries: int = 1, leave_out: float = 0.0, turns: int = 0
    ) -> Search:
        """One placement with frames growing while it is ambiguous (``tries`` of them, the
        first that fits wins). With ``turns`` (and one frame side), a placement whose fit
        correlates ``MARGIN`` short of a copy's is re-fitted from that many turns all round its
        place (:func:`refit_all_round`)."""
        return cls((Round(None if frames is None else tuple(frames), tries, leave_out),), turns=turns)

    @classmethod
    def compared(cls, frames: Sequence[int], copies: int) -> Search:
        """Up to ``copies`` placements at the first frame and the best one at each larger frame
        (each leaving out half its frame about it), compared as the frame grows."""
        sides = tuple(int(size) for size in frames)
        rounds = tuple(Round((size,), copies if k == 0 else 1, size / 2.0) for k, size in enumerate(sides))
        return cls(rounds, sides)


@in_stage("perception")
def match_observation(
    observation: np.ndarray,
    world: np.ndarray,
    point: tuple[float, float],
    object_size: float,
    search: Search,
    observation_features: Features | None = None,
    world_features: Features | None = None,
    fits: Callable[[Match], bool] | None = None,
    parameters: FrameSearch = DEFAULT_FRAME_SEARCH,
) -> Match | NoMatch:
    """``findBestMatch`` of the recorded ``observation`` (h, w, 3) about ``point`` (x, y px; the
    object's centre in it, ``object_size`` px) in ``world`` (H, W, 3), both RGB uint8, as the
    ``search`` says (see the module's docstring), by the rules ``parameters`` (MARGIN in the
    docstrings is ``parameters.margin``). Precomputed SIFT features of either image may be
    passed. :class:`NoMatch` when no placement fits."""
    observation, world = as_rgb(observation, "observation"), as_rgb(world, "world image")
    if observation_features is None:
        observation_features = extract_features(observation)
    if world_features is None:
        world_features = extract_features(world)
    candidates = _candidates(
        observation, world, point, object_size, search, observation_features, world_features, fits, parameters
    )
    if not candidates:
        return NoMatch("no placement of the observation fits in the world at any frame size")
    chosen, refitted, seen = None, [False] * len(candidates), world.astype(np.float32)
    alive = list(range(len(candidates)))  # the candidates no frame has ruled out yet
    shared, taken = -np.inf, 0  # the best correlation any frame reached so far; the leader
    for size in search.compare:
        scores = _scores(observation, seen, point, size, candidates, alive)
        if chosen is not None and max(scores.values()) < shared - parameters.margin:
            # The frame has grown past what the demonstration and this world share: its best
            # correlation fell MARGIN below the best a smaller frame reached. Measured against
            # the best so far, not the last frame's: the correlation may fall in steps each
            # short of MARGIN (0.99, 0.94, 0.85 as the frame takes in more of the board the
            # new world does not share), and a frame past that decides by chance, against the
            # place the smaller frames put first: their leader stands (pinned in
            # tests/vsl/test_matcher.py).
            break
        # The rules. A frame narrows the candidates down (the paper: context "narrows down the
        # possible matches and leaves only a single matching observation"): one it beats by
        # MARGIN is out for good, so a larger frame, which sees mostly the rest of the board
        # that the new world does not share, cannot bring back a place the smaller frames saw
        # was wrong (a house that already has its roof). And a candidate is ruled out on its
        # place, not on its fit: RANSAC on the few features a small frame holds (two, at
        # times) may fit a copy a few px, degrees or a fifth in scale off, and that copy then
        # correlates poorly although its place is as good as the best one's. So before a frame
        # rules candidates out, whether or not one of the rest stands out, each is re-fitted;
        # when one comes within MARGIN the others are re-fitted too (the comparison stays
        # even-handed) and the frame keeps growing while they stay close. A fit is made at the
        # first, smallest frame: the place and its nearest surroundings, which is what the fit
        # is about (and the cheapest to search).
        for everyone in (False, True):
            best = max(scores.values())
            redo = [i for i in alive if not refitted[i] and (everyone or scores[i] < best - parameters.margin)]
            if not redo:
                break
            for i in redo:
                candidates[i] = refit(observation, seen, point, search.compare[0], candidates[i], parameters)
                refitted[i] = True
            scores = _scores(observation, seen, point, size, candidates, alive)
            if all(scores[i] < max(scores.values()) - parameters.margin for i in redo):
                break  # the re-fitted stay beaten: re-fitting the rest could only widen their lead
        alive = _narrowed(candidates, scores, object_size, parameters.margin)
        unique, taken = len(alive) == 1, alive[0]
        chosen = replace(
            candidates[taken],
            score=float(scores[taken]),
            frame=int(size),
            ambiguous=not unique,
            candidates=len(candidates),
        )
        shared = max(shared, chosen.score)
        if unique and chosen.score >= parameters.min_score:
            break
    if chosen is None:
        match = candidates[0]
        frames = search.rounds[0].frames
        if search.turns and frames is not None and len(frames) == 1:
            # A copy of the object, seen by the same camera, correlates within MARGIN of 1 at
            # its frame; a fit that falls short of that fitted a few features, not the copy,
            # and may be turned far off (RANSAC on a few features can fit a symmetric-looking
            # object at any turn and a wrong scale). It is re-fitted from turns all round its
            # place, as a local re-fit from the fit's own turn cannot reach a copy that far off.
            # A good fit keeps its pose.
            seen = world.astype(np.float32)
            if _correlation(observation, seen, point, frames[0], match.transform) < 1.0 - parameters.margin:
                fitted = refit_all_round(observation, seen, point, frames[0], match, search.turns, parameters)
                match = replace(fitted, frame=match.frame, ambiguous=match.ambiguous, candidates=match.candidates)
        return match
    # The match taken is a place and a pose. A copy of the place, seen by the same camera,
    # correlates within MARGIN of 1 at the first frame (the place and its nearest
    # surroundings); a fit that falls short of that fitted a few features, not the copy, and
    # is re-fitted before it is taken, whether or not a comparison re-fitted it (when the
    # rivals' fits are degenerate nothing is compared, and a poor fit would be taken as it is,
    # a few degrees off). Which place is taken stays as it was; a good fit keeps its pose.
    first = search.compare[0]
    if (
        not refitted[taken]
        and _correlation(observation, seen, point, first, candidates[taken].transform) < 1.0 - parameters.margin
    ):
        fitted = refit(observation, seen, point, first, candidates[taken], parameters)
        score = _correlation(observation, seen, point, chosen.frame, fitted.transform)
        chosen = replace(
            chosen,
            x=fitted.x,
            y=fitted.y,
            theta=fitted.theta,
            score=score,
            transform=fitted.transform,
            decomposition=fitted.decomposition,
        )
    return chosen


def _candidates(
    observation: np.ndarray,
    world: np.ndarray,
    point: tuple[float, float],
    object_size: float,
    search: Search,
    observation_features: Features,
    world_features: Features,
    fits: Callable[[Match], bool] | None,
    parameters: FrameSearch,
) -> list[Match]:
    """The placements that fit, round by round; without comparison frames the first one only."""
    candidates: list[Match] = []
    for round_ in search.rounds:
        remaining = world_features
        for _ in range(round_.tries):
            match = find_best_match(
                observation,
                world,
                point,
                object_size,
                round_.frames,
                observation_features,
                remaining,
                parameters=parameters,
            )
            if isinstance(match, NoMatch):
                break
            if fits is None or fits(match):
                if all(np.hypot(match.x - c.x, match.y - c.y) > object_size / 2.0 for c in candidates):
                    candidates.append(match)
                if not search.compare:
                    return candidates
            away = np.hypot(remaining.keypoints[:, 0] - match.x, remaining.keypoints[:, 1] - match.y) > round_.leave_out
            if away.all():
                break  # nothing about it to leave out: the next search would find it again
            remaining = Features(remaining.keypoints[away], remaining.descriptors[away])
    return candidates


def frame_correlation(
    observation: np.ndarray, world: np.ndarray, point: tuple[float, float], size: int, transform: np.ndarray
) -> float:
    """Normalised cross-correlation (colour) of the square frame of side ``size`` around
    ``point`` in ``observation`` with the world seen through ``transform`` (3, 3)."""
    return _correlation(observation, world.astype(np.float32), point, size, transform)


def refit(
    observation: np.ndarray,
    world: np.ndarray,
    point: tuple[float, float],
    size: int,
    match: Match,
    parameters: FrameSearch = DEFAULT_FRAME_SEARCH,
) -> Match:
    """``match`` re-fitted to the ``world`` (H, W, 3) at the frame of side ``size``:
    made rigid about its place (scale 1: the same camera sees the same board, so a fit that
    scaled the frame fitted its few features, not the copy), then moved and turned about its
    place, steps of ``parameters.refit_step`` px and ``refit_turn`` rad halving down to
    ``refit_stop`` (at most ``refit_moves`` of them), to the nearby
    placement whose frame correlates best with the observation. Its score is that correlation."""
    world = world if world.dtype == np.float32 else world.astype(np.float32)
    here = np.array([match.x, match.y])
    scale = _scale(match.transform)
    if not scale > parameters.degenerate:
        return match  # a fit that collapses the frame to a line or a point has no pose to start from
    transform = _about(here, 0.0, 0.0, 0.0, 1.0 / scale) @ match.transform
    score = _correlation(observation, world, point, size, transform)
    step, turn, moves = parameters.refit_step, parameters.refit_turn, 0
    while step >= parameters.refit_stop and moves < parameters.refit_moves:
        here = (transform @ np.array([point[0], point[1], 1.0]))[:2]
        tried = [
            _about(here, dx, dy, dt) @ transform
            for dx, dy, dt in ((step, 0, 0), (-step, 0, 0), (0, step, 0), (0, -step, 0), (0, 0, turn), (0, 0, -turn))
        ]
        scores = [_correlation(observation, world, point, size, t) for t in tried]
        best = int(np.argmax(scores))
        if scores[best] > score:
            transform, score, moves = tried[best], scores[best], moves + 1
        else:
            step, turn = step / 2.0, turn / 2.0
    x, y = (transform @ np.array([point[0], point[1], 1.0]))[:2]
    decomposition = decompose(transform)
    return replace(
        match,
        x=float(x),
        y=float(y),
        theta=decomposition.theta,
        score=float(score),
        transform=transform,
        decomposition=decomposition,
    )


def refit_all_round(
    observation: np.ndarray,
    world: np.ndarray,
    point: tuple[float, float],
    size: int,
    match: Match,
    turns: int,
    parameters: FrameSearch = DEFAULT_FRAME_SEARCH,
) -> Match:
    """``match`` re-fitted (:func:`refit`) from ``turns`` turns evenly all round its place
    (its own turn the first): the best-correlating of the re-fits.

    A fit that collapsed the frame to a line or a point (RANSAC on a few features in a line) has
    a place but no pose: the turn read from it means nothing (a zero matrix reads as no turn).
    It starts as a rigid copy, unturned, at its place, and the turns all round find its pose."""
    here = np.array([match.x, match.y])
    if not _scale(match.transform) > parameters.degenerate:
        shift = np.array([[1.0, 0.0, match.x - point[0]], [0.0, 1.0, match.y - point[1]], [0.0, 0.0, 1.0]])
        match = replace(match, transform=shift, decomposition=decompose(shift), theta=0.0)
    best = refit(observation, world, point, size, match, parameters)
    for k in range(1, turns):
        transform = _about(here, 0.0, 0.0, 2.0 * np.pi * k / turns) @ match.transform
        fitted = refit(observation, world, point, size, replace(match, transform=transform), parameters)
        if fitted.score > best.score:
            best = fitted
    return best


def _scale(transform: np.ndarray) -> float:
    """The scale of the similarity ``transform`` (3, 3): 0 for a fit that collapsed its frame."""
    return float(np.sqrt(abs(np.linalg.det(transform[:2, :2]))))


def _about(centre: np.ndarray, dx: float, dy: float, turn: float, scale: float = 1.0) -> np.ndarray:
    """The similarity (3, 3) that scales by ``scale`` and turns by ``turn`` about ``centre``
    (x, y px), then shifts by (``dx``, ``dy``)."""
    c, s = scale * np.cos(turn), scale * np.sin(turn)
    x, y = float(centre[0]), float(centre[1])
    return np.array([[c, -s, x + dx - c * x + s * y], [s, c, y + dy - s * x - c * y], [0.0, 0.0, 1.0]])


def _scores(
    observation: np.ndarray,
    world: np.ndarray,
    point: tuple[float, float],
    size: int,
    candidates: list[Match],
    alive: list[int],
) -> dict[int, float]:
    """The frame of side ``size``'s correlation for each ``alive`` candidate (by index)."""
    return {i: _correlation(observation, world, point, size, candidates[i].transform) for i in alive}


def _narrowed(candidates: list[Match], scores: dict[int, float], object_size: float, margin: float) -> list[int]:
    """The candidates (indices) a frame leaves, best first: those within ``margin`` of the best
    one, less those that lie within half an object of a better one (a re-fit may move a
    candidate onto another's place: the same place)."""
    order = sorted(scores, key=lambda i: -scores[i])  # stable: ties keep the search's order
    kept: list[int] = []
    for i in order:
        if scores[i] < scores[order[0]] - margin:
            break
        if all(
            np.hypot(candidates[i].x - candidates[k].x, candidates[i].y - candidates[k].y) > object_size / 2.0
            for k in kept
        ):
            kept.append(i)
    return kept


def _correlation(
    observation: np.ndarray, world: np.ndarray, point: tuple[float, float], size: int, transform: np.ndarray
) -> float:
    """:func:`frame_correlation` with the world (H, W, 3) already float32."""
    half = size / 2.0
    x0, y0 = int(max(0, round(point[0] - half))), int(max(0, round(point[1] - half)))
    x1 = int(min(observation.shape[1], round(point[0] + half)))
    y1 = int(min(observation.shape[0], round(point[1] + half)))
    to_world = transform @ np.array([[1.0, 0.0, x0], [0.0, 1.0, y0], [0.0, 0.0, 1.0]])
    flags = cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP
    seen = cv2.warpPerspective(world, to_world, (x1 - x0, y1 - y0), flags=flags)
    inside = cv2.warpPerspective(np.ones(world.shape[:2], np.float32), to_world, (x1 - x0, y1 - y0), flags=flags) > 0.99
    if inside.sum() < 0.5 * inside.size:
        return -1.0
    a = observation[y0:y1, x0:x1].astype(np.float32)[inside]
    b = seen[inside]
    a, b = a - a.mean(axis=0), b - b.mean(axis=0)
    denominator = float(np.sqrt((a * a).sum() * (b * b).sum()))
    return float((a * b).sum() / denominator) if denominator > 1e-6 else 0.0
