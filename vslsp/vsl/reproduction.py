"""VSL's reproduction of pick-and-place operations (paper, "Methodology", Algorithm 1 part II,
lines 13-15, and "Real-world Experiments": the frames, the pick and place poses and the angles
θ^Pick, θ^Place from the decomposed transform α T_sift = T R_θ R_−φ S_v R_φ P).

For each recorded operation (:mod:`vslsp.vsl.pick_place`), in the new world seen from above:

- pick (:func:`match_object`): the object's SIFT features φ matched against the world's and a
  RANSAC similarity fitted (the paper's SIFT-RANSAC), the best placement winning by its
  inliers; a second placement nearly as good makes the match ambiguous;
- place (:func:`find_place`): the pre-place observation found by the one matcher
  (:func:`~vslsp.vsl.matcher.match_observation`) with frames from
  :data:`~vslsp.vsl.pick_place.PLACE_FRAME` times the biggest object (the paper's two to three), growing while the
  match is ambiguous (adaptive frames) up to :data:`PLACE_GROWTH` times that (:func:`place_frames`);
- :func:`plan_operation`: the transforms map the recorded pick and place points into the world,
  the camera maps them onto the table, and the rotation they apply there gives the object's yaw
  now and at the place; the gripper closes across the object's narrower side, on whichever of
  the equivalent hand angles keeps the wrist's turn smallest;
- :func:`correction`: a last look after the operation; an object the execution left off its
  planned place is picked and placed once more;
- the dictionaries searched instead of followed: :func:`identify` (the classification task:
  which recorded object is in view) and :func:`identify_moved` (turn-taking and user
  intervention: which recorded object the tutor just moved).
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from vslsp.geometry.poses import wrap
from vslsp.stages import in_stage
from vslsp.vision.change import changed_pixels
from vslsp.vision.features import Features, extract_features
from vslsp.vision.matching import Match, NoMatch, frame_sizes
from vslsp.vision.parameters import DEFAULT_OBJECT_FINDING, ObjectFinding
from vslsp.vision.transform import decompose
from vslsp.vsl.matcher import Search, match_observation
from vslsp.vsl.parameters import DEFAULT_REPRODUCTION, Reproduction
from vslsp.vsl.pick_place import (
    PickPlaceDemonstration,
    RecordedOperation,
    TableCamera,
    apply,
    object_candidates,
    table_rotation,
)

PLACE_GROWTH = DEFAULT_REPRODUCTION.place_growth  # the default rules' (vslsp.vsl.parameters.Reproduction)


def match_object(
    demo: PickPlaceDemonstration,
    k: int,
    world: np.ndarray,
    world_features: Features,
    parameters: ObjectFinding = DEFAULT_OBJECT_FINDING,
) -> Match | NoMatch:
    """``findBestMatch`` of operation ``k``'s pre-pick observation in the pre-pick frame: the
    object's features φ_k against the world's, SIFT and RANSAC as in the paper. The score is
    the fraction of φ_k that are inliers; the match is ambiguous when a second placement
    gathers nearly as many. :class:`NoMatch` when the object is not found."""
    op = demo.operations[k]
    missing = f"operation {k + 1}'s object is not in the world (no SIFT-RANSAC match)"
    return features_match(op.features, world_features, op.pick_point, demo.pick_frame, missing, parameters)


def features_match(
    features: Features,
    world_features: Features,
    point: tuple[float, float],
    frame: float,
    missing: str,
    parameters: ObjectFinding = DEFAULT_OBJECT_FINDING,
) -> Match | NoMatch:
    """An object's ``features`` found among the world's (SIFT and RANSAC): ``point`` (px) carried
    by the best placement, the share of the features that are its inliers, ambiguous when a
    second placement gathers nearly as many (``parameters.close``); reported with the ``frame`` side (px).
    :class:`NoMatch` (``missing``) when the object is not found."""
    found = object_candidates(features, world_features, parameters=parameters)
    if not found:
        return NoMatch(missing)
    transform, inliers = found[0]
    x, y = apply(transform, point)
    decomposition = decompose(transform)
    ambiguous = len(found) > 1 and found[1][1] >= parameters.close * inliers
    return Match(
        x,
        y,
        decomposition.theta,
        inliers / len(features),
        int(round(frame)),
        ambiguous,
        len(found),
        transform,
        decomposition,
    )


@dataclass(frozen=True, eq=False)
class PlannedOperation:
    """Where to pick and place in the world: the pick and place matches, the hand's pick and
    place poses (x, y, θ) in the table frame (θ the fingers' closing axis), the grasp width
    (m), and the object's yaw now and at the place (rad)."""

    pick_match: Match
    place_match: Match
    pick: tuple[float, float, float]
    place: tuple[float, float, float]
    grasp_width: float
    yaw_now: float
    yaw_target: float

    def to_dict(self) -> dict:
        return {
            "pick": [round(c, 4) for c in self.pick],
            "place": [round(c, 4) for c in self.place],
            "grasp_width": round(self.grasp_width, 4),
            "yaw_now": round(self.yaw_now, 4),
            "yaw_target": round(self.yaw_target, 4),
            "pick_match": _match_dict(self.pick_match),
            "place_match": _match_dict(self.place_match),
        }


def _match_dict(match: Match) -> dict:
    return {k: round(v, 4) if isinstance(v, float) else v for k, v in match.to_dict().items()}


def place_frames(
    demo: PickPlaceDemonstration,
    world_shape: tuple[int, ...],
    k: int | None = None,
    rules: Reproduction = DEFAULT_REPRODUCTION,
) -> list[int]:
    """The Panda's pre-place frame sides (px) in a world of ``world_shape`` (H, W, ...): from
    the pre-place frame (operation ``k``'s own, when it has one), growing up to
    ``rules.place_growth`` times it."""
    start = first_place_frame(demo, k)
    growth = rules.place_growth
    return [s for s in frame_sizes(start, world_shape) if s <= growth * start + 0.5] or [int(round(start))]


def first_place_frame(demo: PickPlaceDemonstration, k: int | None = None) -> float:
    """The side (px) of operation ``k``'s first pre-place frame: its own when it has one (put
    on an object the tutor's slip had nudged: that object's size), else the demonstration's."""
    own = None if k is None else demo.operations[k].place_frame
    return demo.place_frame if own is None else own


def find_place(demo: PickPlaceDemonstration, k: int, world: np.ndarray, world_features: Features) -> Match | NoMatch:
    """``findBestMatch`` of operation ``k``'s pre-place observation in ``world`` (h, w, 3): one
    placement, its frames (:func:`place_frames`) growing while it is ambiguous.
    :class:`NoMatch` when nothing matches."""
    op, sizes = demo.operations[k], place_frames(demo, world.shape, k)
    if op.place_features is not None:
        return match_below(demo, k, world_features)
    return match_observation(
        op.pre_place,
        world,
        op.place_point,
        first_place_frame(demo, k),
        Search.growing(sizes),
        op.observation_features("pre_place", op.place_point, max(sizes)),
        world_features,
    )


def match_below(demo: PickPlaceDemonstration, k: int, world_features: Features) -> Match | NoMatch:
    """The place of operation ``k``, whose object the tutor put on one its hand had nudged
    (:func:`~vslsp.vsl.slips.record.on_nudged`): that object's features in the
    pre-place observation found in the world as the pick finds its object (SIFT and RANSAC),
    the place point carried by that match. The frame about the place that the slip left
    askew from its surroundings (the base the new world has the disk centred on) would not
    agree with the world; the object below does, wherever it lies."""
    op = demo.operations[k]
    assert op.place_features is not None
    missing = f"operation {k + 1}'s place (the object it goes on) is not in the world"
    return features_match(op.place_features, world_features, op.place_point, first_place_frame(demo, k), missing)


@in_stage("perception")
def plan_operation(
    demo: PickPlaceDemonstration,
    k: int,
    world: np.ndarray,
    camera: TableCamera,
    world_features: Features | None = None,
    pick_match: Match | None = None,
    place_match: Match | None = None,
) -> PlannedOperation | NoMatch:
    """Algorithm 1 lines 13-15 for operation ``k`` in the observed ``world`` (H, W, 3): the
    pick and place matches (given, or found with :func:`match_object` and :func:`find_place`)
    turned into the hand's poses.
    :class:`NoMatch` when an observation is not found in the world."""
    op = demo.operations[k]
    world_features = world_features if world_features is not None else extract_features(world)
    pick = pick_match or match_object(demo, k, world, world_features)
    place = place_match or find_place(demo, k, world, world_features)
    if isinstance(pick, NoMatch):
        return pick
    if isinstance(place, NoMatch):
        return place
    pick_xy = camera.pixel_to_table(*apply(pick.transform, op.pick_point), op.pick_z)
    place_xy = camera.pixel_to_table(*apply(place.transform, op.place_point), op.place_z)
    yaw_now = op.yaw + table_rotation(camera, pick.transform, op.pick_point, op.pick_z, op.pick_z)
    yaw_target = op.yaw + op.turn + table_rotation(camera, place.transform, op.place_point, op.place_z, op.place_z)
    return _hand_poses(op, pick, place, pick_xy, place_xy, yaw_now, yaw_target)


def _hand_poses(
    op: RecordedOperation,
    pick: Match,
    place: Match,
    pick_xy,
    place_xy,
    yaw_now: float,
    yaw_target: float,
    rules: Reproduction = DEFAULT_REPRODUCTION,
) -> PlannedOperation:
    """The hand's pick and place poses for an object of ``op``'s footprint at ``pick_xy`` (m)
    turned ``yaw_now`` that must go to ``place_xy`` turned ``yaw_target``: the fingers close
    across its narrower side, on the branch that keeps the wrist's angles smallest."""
    turn = wrap(yaw_target - yaw_now)
    along, across = op.footprint
    axis = yaw_now if along <= across else yaw_now + np.pi / 2.0
    step = np.pi / 2.0 if abs(along - across) < rules.square * max(along, across) else np.pi
    choices = [axis + n * step for n in range(-4, 5)]
    theta = min(choices, key=lambda a: (max(abs(a), abs(a + turn)), abs(a)))
    return PlannedOperation(
        pick,
        place,
        (float(pick_xy[0]), float(pick_xy[1]), float(theta)),
        (float(place_xy[0]), float(place_xy[1]), float(theta + turn)),
        float(min(along, across)),
        float(yaw_now),
        float(yaw_target),
    )


def correction(
    demo: PickPlaceDemonstration,
    k: int,
    world: np.ndarray,
    camera: TableCamera,
    planned: PlannedOperation,
    world_features: Features | None = None,
    parameters: ObjectFinding = DEFAULT_OBJECT_FINDING,
    rules: Reproduction = DEFAULT_REPRODUCTION,
) -> PlannedOperation | None:
    """A last look after operation ``k`` (the loop closed through perception): the object
    found again in ``world`` (h, w, 3), at the height of its place; when its centre lies more
    than ``rules.correction`` from the planned place (the grasp slid it in the fingers, the
    release nudged it), the pick-and-place that puts it right, else None (also when it is not
    found clearly enough to act on: ``parameters.sure`` inliers). Without ``world_features``
    the robot looks only within a square ``rules.look_around`` times the object's size about the
    planned place (an object further off was not nudged; the look costs a fraction of the whole
    view's)."""
    op = demo.operations[k]
    if world_features is None:
        u, v = camera.table_to_pixel(planned.place[0], planned.place[1], op.place_z)
        half = rules.look_around * op.object_size / 2.0
        around = np.zeros(world.shape[:2], np.uint8)
        around[max(0, int(v - half)) : max(0, int(v + half)), max(0, int(u - half)) : max(0, int(u + half))] = 1
        world_features = extract_features(world, around)
    found = match_object(demo, k, world, world_features, parameters)
    if isinstance(found, NoMatch):
        return None
    if found.ambiguous or found.score * len(op.features) < parameters.sure:
        return None
    centre = camera.pixel_to_table(*apply(found.transform, op.pick_point), op.place_z)
    if np.hypot(centre[0] - planned.place[0], centre[1] - planned.place[1]) <= rules.correction:
        return None
    yaw_now = op.yaw + table_rotation(camera, found.transform, op.pick_point, op.pick_z, op.place_z)
    return _hand_poses(op, found, planned.place_match, centre, planned.place[:2], yaw_now, planned.yaw_target, rules)


def identify(
    demo: PickPlaceDemonstration, world: np.ndarray, world_features: Features, candidates: list[int] | None = None
) -> tuple[int, Match] | None:
    """Search the pre-pick dictionary (the paper's classification task): the operation among
    ``candidates`` (default all) whose object matches ``world`` best (the most RANSAC inliers
    relative to its features). None when none is found."""
    best: tuple[int, Match] | None = None
    for k in candidates if candidates is not None else range(len(demo.operations)):
        match = match_object(demo, k, world, world_features)
        if isinstance(match, NoMatch):
            continue
        if best is None or match.score > best[1].score:
            best = (k, match)
    return best


def identify_moved(
    demo: PickPlaceDemonstration,
    before: np.ndarray,
    after: np.ndarray,
    candidates: list[int],
    parameters: ObjectFinding = DEFAULT_OBJECT_FINDING,
) -> int | None:
    """Which recorded operation's object someone else (the tutor) just moved, seen in the
    observations ``before`` and ``after`` (H, W, 3): the changed pixels hold the object twice,
    where it left (``before``) and where it arrived (``after``); each candidate's features φ
    are matched in both, and the first candidate in order whose object is seen at least
    ``parameters.same_object`` as well as the best one wins (the best seen by
    ``parameters.min_matches`` inliers at least). None when nothing recognisable moved."""
    mask = cv2.dilate(changed_pixels(before, after, blur=5) * 255, np.ones((15, 15), np.uint8))
    if not mask.any():
        return None
    seen = [extract_features(image, mask) for image in (before, after)]
    scores = [min(_matches(demo.operations[k].features, features, parameters) for features in seen) for k in candidates]
    if not scores or max(scores) < parameters.min_matches:
        return None
    return next(k for k, score in zip(candidates, scores) if score >= parameters.same_object * max(scores))


def _matches(features: Features, seen: Features, parameters: ObjectFinding) -> int:
    """RANSAC inliers of an object's ``features`` among the ``seen`` ones (0: not seen)."""
    found = object_candidates(features, seen, 1, parameters)
    return found[0][1] if found else 0
