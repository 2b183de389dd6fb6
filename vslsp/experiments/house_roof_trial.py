"""The house-and-roof simulation of the paper ("Simulation", Figure 4, roof placement): VSL's
disambiguation of alternative matches with adaptive frames, in a 2-D world without a robot.

The world (:mod:`vslsp.worlds.house_roof.board`) holds three identical house bodies and three
identical roofs at any pose on a board with a static baseline (the landmark L that Algorithm 1
line 2 detects). The tutor puts a roof on top of the first two bodies and the third roof
*below* the third body, turned upside down. VSL records each operation with the
:class:`~vslsp.vsl.recorder.Recorder` and the :class:`~vslsp.vsl.demonstration.ImagePlane`
model (Algorithm 1, part I), given its pre-place observation too (the world while the roof is
in the hand), which gives the turn the tutor gave the roof; then it reproduces the task in a
new, randomised world (part II), finding each observation with the one matcher
(:func:`~vslsp.vsl.matcher.match_observation`):

- pick: the pre-pick observation in a frame of 1.5 object sizes (the paper's pre-pick frame:
  about the object; a loose roof then differs from one on a house, and the identical loose
  roofs are interchangeable) gives the pick point and θ_pick;
- place: the pre-place observation, starting from a frame of twice the object (the paper's
  pre-place frame) that either stays fixed or grows (adaptive frame, :func:`place_search`):
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

from dataclasses import dataclass
from typing import TypeVar

import numpy as np

from vslsp.errors import InputError
from vslsp.geometry.poses import Pose2, compose, relative, wrap
from vslsp.geometry.trajectory import PickPlaceTrajectory, TrajectoryParameters, pick_and_place
from vslsp.outcomes import Diagnosis
from vslsp.stages import stage
from vslsp.vision.features import extract_features
from vslsp.vision.matching import FrameMode, Match, NoMatch, frame_sizes
from vslsp.vsl.demonstration import Demonstration, ImagePlane
from vslsp.vsl.matcher import Search, match_observation
from vslsp.vsl.recorder import Recorder
from vslsp.vsl.slips.detect import Moves, UnseenOperation
from vslsp.vsl.slips.restore import separate
from vslsp.worlds.house_roof import HouseBoard, roof_name
from vslsp.worlds.house_roof.board import (
    ANGLE_TOLERANCE,
    DEMONSTRATED,
    POSITION_TOLERANCE,
    SLOTS,
    WORLD_SIZE,
    HouseWorld,
    pose_dict,
)
from vslsp.worlds.house_roof.camera import BoardCamera
from vslsp.worlds.slips import TutorSlips

PIXEL_SIZE = 0.001  # m per px: the board is 96 x 72 cm
REST = (480.0, 800.0, 0.15)  # the hand's rest point: px beyond the bottom edge (robot side), m high
TRAJECTORY = TrajectoryParameters(height=0.08, samples=40)
PICK_FRAME = 1.5  # the pre-pick frame's side, in object sizes
PLACE_FRAME = 2.0  # the pre-place frame's first side, in object sizes (the paper: two to three)
ADAPTIVE_LIMIT = 8.0  # the adaptive pre-place frame grows up to this many object sizes
PICK_TURNS = 12  # a poor pick fit is re-fitted from this many turns all round its place (every 30 deg)
_COPIES = 4  # copies of the place's surroundings looked for (three bodies, and one spare)


@dataclass(frozen=True, eq=False)
class HouseRoofDemonstration:
    """What VSL recorded: the :class:`Demonstration` (pre-pick, pre-place and post
    observations, poses, φ, the turn the tutor gave each roof, as perceived); the tutor's
    worlds before and after (ground truth, for the report only)."""

    demonstration: Demonstration
    world_before: HouseWorld
    world_after: HouseWorld
    slips: tuple[dict, ...] = ()  # per operation with --tutor-slips: moved, operated, disturbed, slip
    moves: tuple[Moves | None, ...] = ()  # per operation with the slip detection: what it found (for pictures)
    actual_posts: tuple[np.ndarray, ...] = ()  # with --tutor-slips: the post observations as seen (slips and all)

    @property
    def pre_place(self) -> tuple[np.ndarray, ...]:
        """The pre-place observations (H, W, 3), in order."""
        return tuple(_recorded(op.pre_place) for op in self.demonstration.operations)

    @property
    def turns(self) -> tuple[float, ...]:
        """The turn (rad) the tutor gave each roof, as perceived, in order."""
        return tuple(_recorded(op.turn) for op in self.demonstration.operations)


_T = TypeVar("_T")


def _recorded(value: _T | None) -> _T:
    assert value is not None  # :func:`demonstrate` records every operation with its pre-place observation
    return value


def demonstrate(seed: int, tutor_slips: float | None = None, detection: bool = True) -> HouseRoofDemonstration:
    """The tutor's demonstration in a seeded world of upright-ish houses: roof k onto body k in
    slot ``DEMONSTRATED[k]``, recorded operation by operation with its pre-place observation.

    With ``tutor_slips`` P the tutor, with probability P per operation, also nudges another
    object as it puts the roof down (:class:`~vslsp.worlds.slips.TutorSlips`, seeded by
    ``seed``; :meth:`HouseBoard.slip_candidates`), after the pre-place observation and before
    the post one. With the ``detection`` VSL finds every object that moved
    (:func:`~vslsp.vsl.slips.restore.separate`) and records the operation from the post observation the
    tutor meant (the disturbed objects restored); without it (the paper's VSL) from the post
    observation as it is."""
    board = HouseBoard.from_layout(HouseWorld.random(seed, body_turn=0.5))
    start = board.state
    recorder = Recorder(ImagePlane(board.observe()))
    tutor = None if tutor_slips is None else TutorSlips(tutor_slips, seed)
    records: list[dict] = []
    found: list[Moves | None] = []
    posts: list[np.ndarray] = []
    for k, slot in enumerate(DEMONSTRATED):
        pre = board.observe()
        board.tutor_move(roof_name(k), None)  # in the hand: the pre-place observation
        pre_place = board.observe()
        board.tutor_move(roof_name(k), compose(board.state.bodies[k], SLOTS[slot]))
        if tutor is None:
            recorder.record(pre, board.observe(), pre_place)
            continue
        drawn = tutor.draw(k, board.slip_candidates(roof_name(k)))
        slip = None if drawn is None else board.nudge(drawn)
        seen = board.observe()
        record: dict = {} if slip is None else {"slip": slip.to_dict()}
        moves, post = (None, seen) if not detection else separate(pre, seen, pre_place)
        found.append(moves)
        posts.append(seen)
        try:
            operation = recorder.record(pre, post, pre_place)
        except InputError as unseen:
            raise UnseenOperation(str(unseen), (*records, record)) from unseen
        if moves is not None:
            record = {**_moved_record(moves, board.state, (operation.pose_post.x, operation.pose_post.y)), **record}
        records.append(record)
    return HouseRoofDemonstration(
        recorder.demonstration(), start, board.state, tuple(records), tuple(found), tuple(posts)
    )


def _moved_record(moves: Moves, state: HouseWorld, recorded: tuple[float, float]) -> dict:
    """The operation's ``moved``, ``operated`` and ``disturbed`` objects, named by the board's
    truth (the object nearest to where each was seen after the operation; the report's names,
    not perception's), and where perception saw each. The operated object is the one recorded
    (seen at ``recorded`` px after the operation): when its features did not identify it, it is
    what changed once the disturbed objects were restored."""
    operated = _name_at(state, recorded)
    disturbed = [_name_at(state, obj.after) for obj in moves.disturbed]
    names = [_name_at(state, obj.after) for obj in moves.moved]
    return {
        "moved": [operated, *disturbed],
        "operated": operated,
        "disturbed": disturbed,
        "moves": [{"object": name, **obj.to_dict()} for name, obj in zip(names, moves.moved)],
    }


def _name_at(state: HouseWorld, point: tuple[float, float]) -> str:
    """The object (roof-j or body-j) nearest to image ``point`` (ground truth)."""
    objects = [(f"body-{j}", pose) for j, pose in enumerate(state.bodies)]
    objects += [(roof_name(j), pose) for j, pose in enumerate(state.roofs) if pose is not None]
    return min(objects, key=lambda o: np.hypot(o[1][0] - point[0], o[1][1] - point[1]))[0]


@dataclass(frozen=True, eq=False)
class OperationResult:
    """One reproduced pick-and-place: the pick and place matches (None when none was found),
    the hand's angles, its trajectory, which roof it grasped, where that roof landed (ground
    truth), the slot it landed in with its errors, and the ``diagnosis``: OK, NO_MATCH,
    GRASP_FAILED, WRONG_PLACE (a house that has its roof already, or no slot at all)."""

    pick: Match | None
    place: Match | None
    theta_pick: float
    theta_place: float
    trajectory: PickPlaceTrajectory | None
    grasped: int | None
    landed: Pose2 | None
    slot: tuple[int, str, float, float] | None
    diagnosis: Diagnosis

    @property
    def success(self) -> bool:
        return self.diagnosis is Diagnosis.OK

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
    camera: BoardCamera | None = None,
) -> Reproduction:
    """Algorithm 1 part II in ``world``: for each recorded operation, find the pre-pick and
    pre-place observations (``frame`` "adaptive" or "fixed", see :func:`place_frames`), move
    the hand along the pick-and-place trajectory, and let the grasped roof land where it ends.

    ``camera`` is the reproduction's camera when a perturbation changed it (moved, other light,
    noise, an occluder, distractors): VSL then matches in board coordinates, its image mapped
    back through the camera's calibration (:meth:`BoardCamera.on_board`)."""
    if frame not in tuple(FrameMode):
        raise InputError(f"unknown frame policy {frame!r}; use 'adaptive' or 'fixed'")
    frame = FrameMode(frame)
    features = features or ObservationFeatures(demo)
    start, results, pre_place_worlds = world, [], []
    for k, operation in enumerate(demo.demonstration.operations):
        with stage("perception"):  # the camera's image of the board
            seen = _observe(world, camera)
        pick = match_observation(
            operation.pre_observation,
            seen,
            (operation.pose_pre.x, operation.pose_pre.y),
            operation.object_size,
            Search.growing([pick_frame(operation.object_size)], turns=PICK_TURNS),
            features.pre_pick[k],
        )
        if isinstance(pick, NoMatch):
            results.append(OperationResult(None, None, 0.0, 0.0, None, None, None, None, Diagnosis.NO_MATCH))
            continue
        grasped = world.roof_at((pick.x, pick.y))
        lifted = world if grasped is None else world.with_roof(grasped, None)
        with stage("perception"):
            seen = _observe(lifted, camera)
        pre_place_worlds.append(seen)
        place = match_observation(
            demo.pre_place[k],
            seen,
            (operation.pose_post.x, operation.pose_post.y),
            operation.object_size,
            place_search(frame, operation.object_size),
            features.pre_place[k],
        )
        if isinstance(place, NoMatch):
            results.append(OperationResult(pick, None, pick.theta, 0.0, None, grasped, None, None, Diagnosis.NO_MATCH))
            continue
        theta_place = pick.theta + wrap(place.theta + demo.turns[k] - pick.theta)  # the shorter turn
        with stage("execution"):  # the hand's motion (the world below is the board's kinematics)
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
                OperationResult(
                    pick, place, pick.theta, theta_place, trajectory, None, None, None, Diagnosis.GRASP_FAILED
                )
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
        diagnosis = Diagnosis.OK if fits and not occupied[slot[0]] else Diagnosis.WRONG_PLACE
        results.append(
            OperationResult(pick, place, pick.theta, theta_place, trajectory, grasped, landed, slot, diagnosis)
        )
    return Reproduction(frame, start, world, tuple(results), tuple(pre_place_worlds))


def _observe(world: HouseWorld, camera: BoardCamera | None) -> np.ndarray:
    """The board as the reproduction's camera sees it, in board coordinates."""
    return world.render() if camera is None else camera.on_board(camera.see(world))


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


def place_search(frame: FrameMode | str, object_size: float) -> Search:
    """How the pre-place observation is found: up to :data:`_COPIES` copies of the place's
    surroundings at the first of the :func:`place_frames` and the best placement at each larger
    one are the candidates, compared by colour correlation as the frame grows until one beats
    the others by ``MARGIN``, each beaten one re-fitted first (a poor RANSAC fit of a free
    body's copy must not lose it the comparison at a frame too small to see the roofs; see
    :func:`~vslsp.vsl.matcher.match_observation`). When none does, the best candidate of the largest frame that
    still sees what the demonstration saw (its best correlation has not dropped ``MARGIN`` below
    the best any smaller frame reached) is taken, flagged ambiguous; with a single (fixed) frame
    that is the first place that matches best. A match taken on a fit that correlates poorly at
    the first frame is re-fitted first (the place stays, the pose is the copy's)."""
    return Search.compared(place_frames(frame, object_size), _COPIES)


def _hand_point(xy: tuple[float, float], z: float = 0.0) -> np.ndarray:
    """A hand position (3,) m from image px and a height (m)."""
    return np.array([xy[0] * PIXEL_SIZE, xy[1] * PIXEL_SIZE, z])
