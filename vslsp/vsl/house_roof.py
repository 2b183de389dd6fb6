"""The house-and-roof simulation of the paper ("Simulation", Figure "3Houses"): VSL's
disambiguation of alternative matches with adaptive frames, in a 2-D world without a robot.

The world (:mod:`vslsp.vsl.house_world`) holds three identical house bodies and three
identical roofs at any pose on a board with a static baseline (the landmark L that Algorithm 1
line 2 detects). The tutor puts a roof on top of the first two bodies and the third roof
*below* the third body, turned upside down. VSL records each operation with the
:class:`DemonstrationRecorder` (Algorithm 1, part I) plus its pre-place observation (the world
while the roof is in the hand) and the turn the tutor gave the roof (image subtraction and a
window search over the angle), then reproduces the task in a new, randomised world (part II):

- pick: ``find_best_match`` of the pre-pick observation in a frame of 1.5 object sizes (the
  paper's pre-pick frame: about the object; a loose roof then differs from one on a house,
  and the identical loose roofs are interchangeable) gives the pick point and θ_pick;
- place: :func:`match_place` finds the pre-place observation, starting from a frame of twice
  the object (the paper's pre-place frame) that either stays fixed or grows (adaptive frame);
  every copy of the place's surroundings is a candidate and the frame grows until one stands
  out, which gives the place point and θ_place (plus the demonstrated turn);
- the paper's trajectory (:mod:`vslsp.geometry.trajectory`) carries the roof rest → pick → place
  → rest.

The fixed frame cannot see whether a house already has its roof and may put the third roof
below a finished house, the paper's wrong reproduction; the adaptive frame grows until the
missing roof is in view. Picking and placing act on the ground truth only through the hand:
the roof under the matched pick point is grasped, and it lands where the hand's trajectory
ends, keeping the grasp's offset. Success is judged on the ground truth (each roof's pose
relative to a body), which perception never reads.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import cv2
import numpy as np

from vslsp.errors import InputError
from vslsp.geometry.poses import Pose2, compose, relative, wrap
from vslsp.geometry.trajectory import PickPlaceTrajectory, TrajectoryParameters, pick_and_place
from vslsp.vision.features import Features, extract_features
from vslsp.vision.image import channel_max
from vslsp.vision.matching import MARGIN, MIN_SCORE, FrameMode, Match, NoMatch, find_best_match, frame_sizes
from vslsp.vsl.demonstration import Demonstration, DemonstrationRecorder
from vslsp.vsl.house_world import (
    ANGLE_TOLERANCE,
    DEMONSTRATED,
    POSITION_TOLERANCE,
    SLOTS,
    WORLD_SIZE,
    HouseWorld,
    pose_dict,
)

PIXEL_SIZE = 0.001  # m per px: the board is 96 x 72 cm
REST = (480.0, 800.0, 0.15)  # the hand's rest point: px beyond the bottom edge (robot side), m high
TRAJECTORY = TrajectoryParameters(height=0.08, samples=40)
PICK_FRAME = 1.5  # the pre-pick frame's side, in object sizes
PLACE_FRAME = 2.0  # the pre-place frame's first side, in object sizes (the paper: two to three)
ADAPTIVE_LIMIT = 8.0  # the adaptive pre-place frame grows up to this many object sizes
_COPIES = 4  # copies of the place's surroundings looked for (three bodies, and one spare)
_PATCH = 128  # px, side of the window the demonstrated turn is searched in (a roof is 60 px across)


@dataclass(frozen=True, eq=False)
class HouseRoofDemonstration:
    """What VSL recorded: the :class:`Demonstration` (pre-pick and post observations, poses,
    φ), the pre-place observations (H, W, 3) and the turn (rad) the tutor gave each roof, as
    perceived; the tutor's worlds before and after (ground truth, for the report only)."""

    demonstration: Demonstration
    pre_place: tuple[np.ndarray, ...]
    turns: tuple[float, ...]
    world_before: HouseWorld
    world_after: HouseWorld


def demonstrate(seed: int) -> HouseRoofDemonstration:
    """The tutor's demonstration in a seeded world of upright-ish houses: roof k onto body k in
    slot ``DEMONSTRATED[k]``, recorded operation by operation."""
    world = start = HouseWorld.random(seed, body_turn=0.5)
    recorder = DemonstrationRecorder(world.render())
    pre_place, turns = [], []
    for k, slot in enumerate(DEMONSTRATED):
        pre = world.render()
        lifted = world.with_roof(k, None)
        pre_place.append(lifted.render())
        world = lifted.with_roof(k, compose(world.bodies[k], SLOTS[slot]))
        post = world.render()
        recorder.record(pre, post)
        turns.append(perceived_turn(pre, pre_place[-1], post))
    return HouseRoofDemonstration(recorder.demonstration(), tuple(pre_place), tuple(turns), start, world)


def perceived_turn(pre: np.ndarray, pre_place: np.ndarray, post: np.ndarray) -> float:
    """How far (rad) the tutor turned the moved object: its pixels are where the pre-pick and
    the post-place observations (H, W, 3) differ from the pre-place one (image subtraction),
    and the turn is the rotation that best lays the first patch onto the second (a window
    search over the angle, 3° steps refined to 0.05°)."""
    before, before_mask = _object_patch(pre, pre_place)
    after, after_mask = _object_patch(post, pre_place)

    def mismatch(angle: float) -> float:
        turn = cv2.getRotationMatrix2D((_PATCH / 2.0, _PATCH / 2.0), -np.degrees(angle), 1.0)
        grey = cv2.warpAffine(before, turn, (_PATCH, _PATCH), flags=cv2.INTER_LINEAR)
        mask = cv2.warpAffine(before_mask, turn, (_PATCH, _PATCH), flags=cv2.INTER_LINEAR)
        union = cv2.max(mask, after_mask)
        return float(cv2.absdiff(grey, after).ravel() @ union.ravel() / max(float(union.sum()), 1.0))

    angle = 0.0
    for step, reach in ((3.0, 180.0), (0.25, 3.0), (0.05, 0.25)):  # coarse to fine window search
        angles = angle + np.radians(np.arange(-reach, reach, step))
        angle = float(angles[int(np.argmin([mismatch(a) for a in angles]))])
    return wrap(angle)


def _object_patch(image: np.ndarray, without: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The object that ``image`` has and ``without`` lacks: a grey window (P, P) float32 of
    ``image`` centred on the changed pixels' centroid, masked by them (P, P) float32."""
    changed = (channel_max(cv2.absdiff(image, without)) > 40).astype(np.uint8)
    changed = cv2.morphologyEx(changed, cv2.MORPH_OPEN, np.ones((3, 3), np.uint8))
    ys, xs = np.nonzero(changed)
    if len(xs) < 50:
        raise InputError(
            "the moved object is not seen in the demonstration's observations; "
            "keep it in view and let it differ from the board"
        )
    shift = np.array([[1.0, 0.0, _PATCH / 2.0 - xs.mean()], [0.0, 1.0, _PATCH / 2.0 - ys.mean()]])
    grey = cv2.cvtColor(image, cv2.COLOR_RGB2GRAY).astype(np.float32)
    patch = cv2.warpAffine(grey, shift, (_PATCH, _PATCH), flags=cv2.INTER_LINEAR)
    mask = cv2.warpAffine(changed.astype(np.float32), shift, (_PATCH, _PATCH), flags=cv2.INTER_LINEAR)
    return patch * mask, mask


@dataclass(frozen=True, eq=False)
class OperationResult:
    """One reproduced pick-and-place: the pick and place matches (None when none was found),
    the hand's angles, its trajectory, which roof it grasped, where that roof landed (ground
    truth), the slot it landed in with its errors, and the ``diagnosis``: "ok", "no match",
    "grasp failed", "wrong place" (a house that has its roof already, or no slot at all)."""

    pick: Match | None
    place: Match | None
    theta_pick: float
    theta_place: float
    trajectory: PickPlaceTrajectory | None
    grasped: int | None
    landed: Pose2 | None
    slot: tuple[int, str, float, float] | None
    diagnosis: str

    @property
    def success(self) -> bool:
        return self.diagnosis == "ok"

    def to_dict(self) -> dict:
        return {
            "diagnosis": self.diagnosis,
            "pick": None if self.pick is None else self.pick.to_dict(),
            "place": None if self.place is None else self.place.to_dict(),
            "theta_pick": round(self.theta_pick, 5),
            "theta_place": round(self.theta_place, 5),
            "grasped_roof": self.grasped,
            "landed": None if self.landed is None else pose_dict(self.landed),
            "body": None if self.slot is None else self.slot[0],
            "slot": None if self.slot is None else self.slot[1],
            "position_error_px": None if self.slot is None else round(self.slot[2], 3),
            "angle_error_deg": None if self.slot is None else round(float(np.degrees(self.slot[3])), 3),
        }


@dataclass(frozen=True, eq=False)
class Reproduction:
    """A reproduction with one frame policy: the worlds before and after, each operation, and
    whether the final world reaches the demonstrated goal (ground truth)."""

    frame: FrameMode
    world_before: HouseWorld
    world_after: HouseWorld
    operations: tuple[OperationResult, ...]
    pre_place_worlds: tuple[np.ndarray, ...]

    @property
    def success(self) -> bool:
        return self.world_after.goal_reached()

    def to_dict(self) -> dict:
        return {
            "frame": FrameMode(self.frame).value,
            "success": self.success,
            "operations": [op.to_dict() for op in self.operations],
            "houses": {str(k): v for k, v in self.world_after.houses().items()},
            "world_after": self.world_after.to_dict(),
        }


class ObservationFeatures:
    """SIFT features of the recorded observations, extracted once per demonstration."""

    def __init__(self, demo: HouseRoofDemonstration) -> None:
        self.pre_pick = [extract_features(image) for image in demo.demonstration.pre_observations]
        self.pre_place = [extract_features(image) for image in demo.pre_place]


def reproduce(
    demo: HouseRoofDemonstration,
    world: HouseWorld,
    frame: FrameMode | str = FrameMode.ADAPTIVE,
    features: ObservationFeatures | None = None,
) -> Reproduction:
    """Algorithm 1 part II in ``world``: for each recorded operation, find the pre-pick and
    pre-place observations (``frame`` "adaptive" or "fixed", see :func:`place_frames`), move
    the hand along the pick-and-place trajectory, and let the grasped roof land where it ends."""
    if frame not in tuple(FrameMode):
        raise InputError(f"unknown frame policy {frame!r}; use 'adaptive' or 'fixed'")
    frame = FrameMode(frame)
    features = features or ObservationFeatures(demo)
    start, results, pre_place_worlds = world, [], []
    for k, operation in enumerate(demo.demonstration.operations):
        seen = world.render()
        pick = find_best_match(
            operation.pre_observation,
            seen,
            (operation.pose_pre.x, operation.pose_pre.y),
            operation.object_size,
            [pick_frame(operation.object_size)],
            features.pre_pick[k],
        )
        if isinstance(pick, NoMatch):
            results.append(OperationResult(None, None, 0.0, 0.0, None, None, None, None, "no match"))
            continue
        grasped = world.roof_at((pick.x, pick.y))
        lifted = world if grasped is None else world.with_roof(grasped, None)
        seen = lifted.render()
        pre_place_worlds.append(seen)
        place = match_place(
            demo.pre_place[k],
            seen,
            (operation.pose_post.x, operation.pose_post.y),
            operation.object_size,
            place_frames(frame, operation.object_size),
            features.pre_place[k],
        )
        if isinstance(place, NoMatch):
            results.append(OperationResult(pick, None, pick.theta, 0.0, None, grasped, None, None, "no match"))
            continue
        theta_place = pick.theta + wrap(place.theta + demo.turns[k] - pick.theta)  # the shorter turn
        trajectory = pick_and_place(
            _hand_point(REST[:2], REST[2]),
            _hand_point((pick.x, pick.y)),
            _hand_point((place.x, place.y)),
            pick.theta,
            theta_place,
            TRAJECTORY,
        )
        if grasped is None:
            results.append(
                OperationResult(pick, place, pick.theta, theta_place, trajectory, None, None, None, "grasp failed")
            )
            continue
        hand_at_pick = (pick.x, pick.y, pick.theta)
        end = trajectory.segments[2]
        hand_at_place = (*(trajectory.xyz[end, :2] / PIXEL_SIZE), float(trajectory.theta[end]))
        held = world.roofs[grasped]
        assert held is not None  # the roof found under the hand lies on the board
        landed = compose(hand_at_place, relative(hand_at_pick, held))
        occupied = world.houses()
        world = lifted.with_roof(grasped, landed)
        slot = world.slot_of(landed)
        fits = slot[2] <= POSITION_TOLERANCE and slot[3] <= ANGLE_TOLERANCE and slot[1] == DEMONSTRATED[k]
        diagnosis = "ok" if fits and not occupied[slot[0]] else "wrong place"
        results.append(
            OperationResult(pick, place, pick.theta, theta_place, trajectory, grasped, landed, slot, diagnosis)
        )
    return Reproduction(frame, start, world, tuple(results), tuple(pre_place_worlds))


def pick_frame(object_size: float) -> int:
    """The pre-pick frame side (px): the object with a rim of its surroundings (a roof on a
    house then differs from a loose one); identical loose roofs are interchangeable, so it
    does not grow."""
    return int(round(PICK_FRAME * object_size))


def place_frames(frame: FrameMode | str, object_size: float) -> list[int]:
    """The pre-place frame sides (px) to try: from :data:`PLACE_FRAME` object sizes, ×1.5 up to
    :data:`ADAPTIVE_LIMIT` object sizes ("adaptive"), or the first of them only ("fixed"), too
    small to see whether a house already has its roof. Beyond the limit a frame sees mostly
    the rest of the board, which the randomised world does not share, and a match there that
    stands out is chance."""
    sizes = frame_sizes(PLACE_FRAME * object_size, (WORLD_SIZE[1], WORLD_SIZE[0]))
    if FrameMode(frame) is FrameMode.FIXED:
        return sizes[:1]
    return [size for size in sizes if size <= ADAPTIVE_LIMIT * object_size] or sizes[:1]


def match_place(
    observation: np.ndarray,
    world: np.ndarray,
    point: tuple[float, float],
    object_size: float,
    sizes: list[int],
    observation_features: Features,
) -> Match | NoMatch:
    """``findBestMatch`` of a pre-place observation (h, w, 3) in ``world`` (H, W, 3) with frames
    of the given ``sizes`` (px, growing): every copy of the place's surroundings is a candidate
    (found by ``find_best_match`` with the copies already found left out, and at each size), and
    the frame grows until one candidate's correlation beats all others by ``MARGIN``. When none
    does, the best candidate of the largest frame that still sees what the demonstration saw
    (the best correlation has not dropped by ``MARGIN``) is returned, flagged ambiguous; with a
    single (fixed) size that is the first place that matches best. :class:`NoMatch` when
    nothing matches at all."""
    world_features = extract_features(world)
    candidates: list[Match] = []
    for index, size in enumerate(sizes):
        remaining = world_features
        for _ in range(_COPIES if index == 0 else 1):
            match = find_best_match(observation, world, point, object_size, [size], observation_features, remaining)
            if isinstance(match, NoMatch):
                break
            if all(np.hypot(match.x - c.x, match.y - c.y) > object_size / 2.0 for c in candidates):
                candidates.append(match)
            away = np.hypot(remaining.keypoints[:, 0] - match.x, remaining.keypoints[:, 1] - match.y) > size / 2.0
            remaining = Features(remaining.keypoints[away], remaining.descriptors[away])
    if not candidates:
        return NoMatch("no SIFT match of the pre-place observation in the world")
    chosen = None
    for size in sizes:
        scores = np.array([frame_correlation(observation, world, point, size, c.transform) for c in candidates])
        order = np.argsort(-scores, kind="stable")
        if chosen is not None and scores[order[0]] < chosen.score - MARGIN:
            break  # the frame has grown past what the demonstration and this world share
        unique = len(candidates) == 1 or scores[order[0]] - scores[order[1]] >= MARGIN
        chosen = replace(
            candidates[order[0]],
            score=float(scores[order[0]]),
            frame=int(size),
            ambiguous=not unique,
            candidates=len(candidates),
        )
        if unique and chosen.score >= MIN_SCORE:
            break
    return chosen if chosen is not None else NoMatch("no frame size gave a placement of the pre-place observation")


def frame_correlation(
    observation: np.ndarray, world: np.ndarray, point: tuple[float, float], size: int, transform: np.ndarray
) -> float:
    """Normalised cross-correlation (colour) of the square frame of side ``size`` around
    ``point`` in ``observation`` with the world seen through ``transform`` (3, 3)."""
    half = size / 2.0
    x0, y0 = int(max(0, round(point[0] - half))), int(max(0, round(point[1] - half)))
    x1 = int(min(observation.shape[1], round(point[0] + half)))
    y1 = int(min(observation.shape[0], round(point[1] + half)))
    to_world = transform @ np.array([[1.0, 0.0, x0], [0.0, 1.0, y0], [0.0, 0.0, 1.0]])
    flags = cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP
    seen = cv2.warpPerspective(world.astype(np.float32), to_world, (x1 - x0, y1 - y0), flags=flags)
    inside = cv2.warpPerspective(np.ones(world.shape[:2], np.float32), to_world, (x1 - x0, y1 - y0), flags=flags) > 0.99
    if inside.sum() < 0.5 * inside.size:
        return -1.0
    a = observation[y0:y1, x0:x1].astype(np.float32)[inside]
    b = seen[inside]
    a, b = a - a.mean(axis=0), b - b.mean(axis=0)
    denominator = float(np.sqrt((a * a).sum() * (b * b).sum()))
    return float((a * b).sum() / denominator) if denominator > 1e-6 else 0.0


def _hand_point(xy: tuple[float, float], z: float = 0.0) -> np.ndarray:
    """A hand position (3,) m from image px and a height (m)."""
    return np.array([xy[0] * PIXEL_SIZE, xy[1] * PIXEL_SIZE, z])


def frame_box(match: Match, size: int, point: tuple[float, float]) -> np.ndarray:
    """The corners (4, 2) px in the world of the square frame of side ``size`` around the
    recorded ``point``, mapped through the match's transform (for overlays)."""
    half = size / 2.0
    corners = np.array(
        [
            [point[0] - half, point[1] - half],
            [point[0] + half, point[1] - half],
            [point[0] + half, point[1] + half],
            [point[0] - half, point[1] + half],
        ],
        np.float32,
    )
    return cv2.perspectiveTransform(corners[None], match.transform)[0]
