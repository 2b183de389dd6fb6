"""Every object that moved in one demonstrated operation, and which of them the operation was
about (issue 30: the tutor's slips; the paper's own limit, VSL "Results": "if the tutor
accidentally moves one object while operating another, the algorithm may fail").

Algorithm 1 line 7 (``getObject``) takes the change between the pre- and the post-action
observation for the one object the tutor operated. When the tutor's hand also nudged another
object, :func:`find_moved` finds each of them:

1. image subtraction and thresholding of the pre and post observations (H, W, 3), closed into
   changed regions (those of at least :data:`MIN_REGION` px);
2. per-object identification by matching: the SIFT features of the pre observation inside each
   region are matched to those of the post observation inside the changed pixels (both nearest
   descriptors of each, so that identical objects, the house-roof board's roofs, still match),
   and RANSAC fits similarities one after the other (at least :data:`MIN_INLIERS` inliers, a
   scale within :data:`~vslsp.vision.matching.SCALE_RANGE`); each placement that moves its
   features is one object's move (one that leaves them where they were is the unchanged rim);
3. one object per place: the placements are taken nearest first (a slip nudges an object by a
   few cm, an operation carries one from its place to another, so the pairing that moves
   objects least is the right one when two objects look alike), each pre keypoint used once
   and a fit a quarter of whose post keypoints another object took already refused; a fit
   waits for one from where the same object was that explains it twice as well and whose place
   is free (objects that share part of their look), unless it explains its object whole
   (``SlipRules.well``: then the two are identical objects and the nearer stands); a second pass
   pairs the regions left unexplained with the post keypoints left. Given the pre-place
   observation, when this pairing leaves out the object the tutor took (another object's short
   fit took its arrival), it is paired again with the taken object's fits first;
4. the slips the pre observation cannot show (:func:`_uncovered_slips`): the hand slips after
   the object is taken, so the nudges between the pre-place and post observations are slips
   too (a disk that the operated one covered, nudged once uncovered).

The rule for the operated object (:func:`_decide`): **the one that left its place for another**
(its old and new places are different changed regions; given the pre-place observation, it
left from where that one lacks what the pre one shows; the farthest moved if several): a
pick-and-place carries the object from its place to another, the tutor's slip nudges one by a
few cm, so that its old and new places make one region (or lie less than twice its keypoints'
spread apart). Those others are disturbed, except what changed where the operated object left
or arrived (what it covered or uncovered). When the
operated object's features do not identify it, it is what changed once the disturbed objects
are restored.

The reproduction must not copy the accident: :func:`vslsp.vsl.slips.restore.separate` gives the post observation the
tutor meant, the disturbed objects' changed pixels restored from the pre-place observation
(the operated object already taken, so a disk it lay on comes back without it; the pre one
when there is none), each changed pixel of a region a disturbed object moved in going to the
object whose identified keypoints are nearest, so that the operation is recorded as if only the operated object had
moved: no disturbed object is taken for the operation, and no place for the operated object's
is measured against a neighbour the tutor knocked aside. With the detection off (the paper's
VSL) the observations are recorded as they are.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import cv2
import numpy as np

from vslsp.errors import InputError
from vslsp.vision.change import changed_pixels
from vslsp.vision.features import Features, extract_features
from vslsp.vision.matching import SCALE_RANGE
from vslsp.vsl.slips.parameters import DEFAULT_SLIP_RULES, SlipRules

MIN_REGION = DEFAULT_SLIP_RULES.min_region  # the default rules' (vslsp.vsl.slips.parameters.SlipRules)
MIN_INLIERS = DEFAULT_SLIP_RULES.min_inliers
EXPLAINS = DEFAULT_SLIP_RULES.explains
STILL_PX, STILL_DEG = 3.0, 2.0  # a placement moving its features less than this is no move
_CLOSE = np.ones((9, 9), np.uint8)
_RIM = np.ones((15, 15), np.uint8)  # the features of a region's rim are its object's too


@dataclass(frozen=True, eq=False)
class MovedObject:
    """One object that moved: where it was in the pre observation and where it is in the post
    one (the centre of its matched features, (x, y) px), the turn (rad, image coordinates), its
    matched keypoints before (N, 2) and after (N, 2) px."""

    before: tuple[float, float]
    after: tuple[float, float]
    turn: float
    keypoints_before: np.ndarray
    keypoints_after: np.ndarray
    transform: np.ndarray = field(default_factory=lambda: np.eye(2, 3), repr=False)  # (2, 3) px, pre -> post
    mismatch: float = 0.0  # what is left of the difference once moved (share of it left in place)

    @property
    def distance(self) -> float:
        """How far it moved (px)."""
        return float(np.hypot(self.after[0] - self.before[0], self.after[1] - self.before[1]))

    def to_dict(self) -> dict:
        return {
            "before_px": [round(c, 1) for c in self.before],
            "after_px": [round(c, 1) for c in self.after],
            "distance_px": round(self.distance, 1),
            "turn_deg": round(float(np.degrees(self.turn)), 1),
        }


@dataclass(frozen=True, eq=False)
class Moves:
    """The objects that moved in one operation: the ``operated`` one (None when its features
    did not identify it: then it is what changed once the disturbed ones are restored) and the
    ``disturbed`` ones, farthest first."""

    operated: MovedObject | None
    disturbed: tuple[MovedObject, ...]

    @property
    def moved(self) -> tuple[MovedObject, ...]:
        """Every object identified as moved, the operated one first."""
        return (self.operated, *self.disturbed) if self.operated is not None else self.disturbed


class UnseenOperation(InputError):
    """The recorder could not see the tutor's operation; ``slips``: the report's records of the
    operations so far (per operation: what moved, which one was operated, the tutor's slip),
    this one's last."""

    def __init__(self, message: str, slips: tuple[dict, ...]) -> None:
        super().__init__(message)
        self.slips = slips


def changes_between(pre: np.ndarray, post: np.ndarray) -> np.ndarray:
    """The changes the slip rules see: the pixels (H, W) uint8 {0, 1} that changed between the
    observations (H, W, 3) uint8 (:func:`~vslsp.vision.change.changed_pixels`), smoothed (5 px),
    closed over small gaps (:data:`_CLOSE`)."""
    return changed_pixels(pre, post, blur=5, close=_CLOSE)


def find_moved(
    pre: np.ndarray, post: np.ndarray, pre_place: np.ndarray | None = None, rules: SlipRules = DEFAULT_SLIP_RULES
) -> Moves:
    """Every object that moved between the pre and post observations (H, W, 3) uint8, the
    operated one told from the disturbed ones (see the module docstring for the steps and the
    rule); given the pre-place observation (H, W, 3: the world while the tutor held the object)
    the operated object is one that the pre-place observation lacks; ``rules`` are its thresholds."""
    setup = _pairing(pre, post, rules)
    if setup is None:
        return Moves(None, ())
    pairing, grown = setup
    # Where the pre-place observation lacks what the pre one shows: the object the tutor took.
    taken = None if pre_place is None else cv2.dilate(changes_between(pre, pre_place), np.ones((5, 5), np.uint8))
    moved = _pair(*pairing, rules=rules)
    if pre_place is None:
        return _decide(moved, grown, None, rules)
    moves = _decide(moved, grown, taken, rules)
    nudges = _nudges(pre_place, post, rules)
    if moves.operated is None and taken is not None:
        # The object the tutor took moved for sure. When the nearest-first pairing left it out
        # (a short fit of another object onto its arrival took its place: disks whose look it
        # shares in part, under it there), it is paired first; unless that puts it where a
        # nudge seen between the pre-place and post observations ended (identical roofs: the
        # taken one's fit onto the nudged one's new place, its own arrival showing too few
        # features to fit; the nudge is the slip, and the arrival is left to the recorder). Only
        # a nudge that explains its object well (``rules.nudge_well``) overrules it: a fit of the
        # disk below onto a disk put on it explains it in part only (about half the difference
        # is left, where a true nudge of an identical object leaves an eighth at most).
        first = _decide(_pair(*pairing, first=taken, rules=rules), grown, taken, rules)
        if first.operated is not None and not any(
            _same_place(first.operated, nudge, rules.same_px) and nudge.mismatch <= rules.nudge_well for nudge in nudges
        ):
            moves = first
    return _uncovered_slips(moves, nudges, rules.same_px)


def _nudges(pre_place: np.ndarray, post: np.ndarray, rules: SlipRules) -> list[MovedObject]:
    """The slips seen after the object was taken: the moves between the pre-place and post
    observations no longer than twice the object's keypoint spread (a nudge; a longer one is a
    fit of something else's look: the identical bases of the Tower of Hanoi, one uncovered by
    the slip, another covered by the arrival)."""
    setup = _pairing(pre_place, post, rules)
    moved = _pair(*setup[0], rules=rules) if setup is not None else []
    return [obj for obj in moved if obj.distance <= 2.0 * _spread(obj.keypoints_before)]


# What _pair pairs: the pre and post features, the changed regions' labels, each pre keypoint's
# region, the changed pixels (H, W) and the images (pre, post).
_Pairing = tuple[Features, Features, list[int], np.ndarray, np.ndarray, tuple[np.ndarray, np.ndarray]]


def _pairing(pre: np.ndarray, post: np.ndarray, rules: SlipRules) -> tuple[_Pairing, np.ndarray] | None:
    """What :func:`_pair` pairs between ``pre`` and ``post`` (H, W, 3) uint8: the features of
    both in and about the changed regions (steps 1 and 2 of the module docstring), each pre
    keypoint's region, the changed pixels and the images; and the regions (H, W) labels, grown
    by a rim. None when nothing changed or too few features lie there."""
    changed = changes_between(pre, post)
    count, labels, stats, _ = cv2.connectedComponentsWithStats(changed)
    regions = [k for k in range(1, count) if stats[k, cv2.CC_STAT_AREA] >= rules.min_region]
    if not regions:
        return None
    area = cv2.dilate(np.isin(labels, regions).astype(np.uint8), _RIM)
    before, after = extract_features(pre, area), extract_features(post, area)
    if len(before) < rules.min_inliers or len(after) < rules.min_inliers:
        return None
    # Each pre keypoint belongs to the region it lies in (or next to).
    grown = cv2.dilate(labels.astype(np.float32), _RIM).astype(np.int32)
    where = np.clip(np.round(before.keypoints[:, :2]).astype(int), 0, [pre.shape[1] - 1, pre.shape[0] - 1])
    owner = grown[where[:, 1], where[:, 0]]
    on_change = cv2.dilate(changed, np.ones((5, 5), np.uint8))
    return (before, after, regions, owner, on_change, (pre, post)), grown


def _pair(
    before: Features,
    after: Features,
    regions: list[int],
    owner: np.ndarray,
    on_change: np.ndarray,
    images: tuple[np.ndarray, np.ndarray],
    first: np.ndarray | None = None,
    rules: SlipRules = DEFAULT_SLIP_RULES,
) -> list[MovedObject]:
    """The objects that moved: the placements of the pre keypoints of each changed region
    (``owner``: each keypoint's region) among the post ones, paired one object per place
    (steps 2 and 3 of the module docstring); the fits that leave from the pixels ``first``
    (H, W), when given, before the others."""
    used_before: set[int] = set()
    used_after: set[int] = set()
    moved: list[MovedObject] = []
    # Two passes: the second pairs what is left unexplained (a region whose object's features
    # also fit an identical object's new place, taken by that object in the first pass) with
    # the post keypoints no object has taken yet.
    for _ in range(2):
        free = np.array(sorted(set(range(len(after))) - used_after), int)
        candidates: list[tuple[float, MovedObject, np.ndarray, np.ndarray]] = []
        for region in regions:
            members = np.nonzero(owner == region)[0]
            if not used_before & set(members.tolist()):
                candidates += _placements(before, after, members, free, on_change, images, rules)
        # One object per place, nearest first: each keypoint of either observation is used once;
        # a fit waits for a later one from where the same object was that explains it
        # ``rules.rival`` times better and whose place is still free (an object whose look
        # others share in part fits onto them too, worse).
        candidates.sort(key=lambda c: (first is not None and not _on(first, before.keypoints[c[2]]), c[0]))

        def available(
            candidate: tuple[float, MovedObject, np.ndarray, np.ndarray],
            taken_before: set[int],
            taken_after: set[int],
            placed: list[MovedObject],
        ) -> bool:
            """Whether no accepted object took the fit's pre keypoints, a quarter of its post
            ones, or the place it puts its object (each place holds one object)."""
            _, obj, sources, targets = candidate
            return (
                not taken_before & set(sources.tolist())
                and 4 * len(taken_after & set(targets.tolist())) <= len(targets)
                and not any(_same_place(obj, other, rules.same_px) for other in placed)
            )

        for k, candidate in enumerate(candidates):
            _, obj, sources, targets = candidate
            if not available(candidate, used_before, used_after, moved) or any(
                _same_object(obj, other, rules.same_px) for other in moved
            ):
                continue
            if obj.mismatch > rules.well and any(
                _same_object(obj, later[1], rules.same_px)
                and rules.rival * later[1].mismatch < obj.mismatch
                and available(later, used_before, used_after, moved)
                for later in candidates[k + 1 :]
            ):
                continue
            used_before |= set(sources.tolist())
            used_after |= set(targets.tolist())
            moved.append(obj)
    return moved


def _uncovered_slips(moves: Moves, nudges: list[MovedObject], rim: float) -> Moves:
    """``moves`` with the objects the operated one covered in the pre observation that the
    tutor's hand then nudged. The rule: the hand slips after the object is taken, so every
    nudge between the pre-place observation (the operated object held out of view, what it
    covered uncovered) and the post observation (:func:`_nudges`) is disturbed, apart from the
    operated object's arrival. A disk taken from the one it lay on hides all but a sliver of it
    in the pre observation, too little to identify it there (Tower of Hanoi: the tutor lifts
    disk 1 off disk 2 and nudges disk 2); in the pre-place one it lies whole. A fit ending
    where the operated object arrived is of the arrival (a disk put on another, their looks
    alike in part), not a slip."""
    found = [
        obj
        for obj in nudges
        if not any(_same_object(obj, other, rim) or _same_place(obj, other, rim) for other in moves.disturbed)
        and (moves.operated is None or not _arrives(moves.operated, obj, rim))
    ]
    if not found:
        return moves
    return Moves(moves.operated, tuple(sorted((*moves.disturbed, *found), key=lambda o: -o.distance)))


def _arrives(operated: MovedObject, other: MovedObject, rim: float) -> bool:
    """Whether ``other``'s move ends where ``operated`` arrived (within its keypoint spread and
    a rim of ``rim`` px): a fit of the operated object's arrival, or of what it covered there."""
    reach = _spread(operated.keypoints_after) + rim
    return bool(np.hypot(*np.subtract(operated.after, other.after)) <= reach)


def _decide(moved: list[MovedObject], regions: np.ndarray, taken: np.ndarray | None, rules: SlipRules) -> Moves:
    """The rule: the operated object is the one that left its place for another (where it was
    and where it is lie in different changed regions of ``regions`` (H, W) labels; given the
    pixels ``taken`` (H, W) where the pre-place observation lacks what the pre one shows, it
    left from there), the farthest moved if several. The others are disturbed when they were
    nudged: their old and new places make one changed region, or the move is shorter than
    twice the object's keypoint spread (a slip moves an object by about its own size at most; a
    longer move from elsewhere is a fit of something else's look, an identical object's). What
    changed where the operated object left or arrived is the operation's (what it covered or
    uncovered there), not another object's move."""
    leaving = [obj for obj in moved if _label(regions, obj.before) != _label(regions, obj.after)]
    carried = [obj for obj in leaving if taken is None or _on(taken, obj.keypoints_before)]
    if not carried and taken is not None:
        # The tutor took it (the pre-place observation lacks it) and put it down beside where
        # it was, so that its two places make one changed region: still the operation, not a
        # nudge (domino: the piece a slip had pushed out of line, next put at the row's end).
        carried = [obj for obj in moved if _on(taken, obj.keypoints_before)]
    operated = max(carried, key=lambda o: o.distance) if carried else None
    disturbed = [
        obj
        for obj in moved
        if obj is not operated and (obj not in leaving or obj.distance <= 2.0 * _spread(obj.keypoints_before))
    ]
    if operated is not None:
        disturbed = [obj for obj in disturbed if not _within(operated, obj, rules.same_px)]
    return Moves(operated, tuple(sorted(disturbed, key=lambda o: -o.distance)))


def keypoint_area(shape: tuple[int, ...], point_sets) -> np.ndarray:
    """The pixels (H, W) uint8 {0, 1} of ``shape`` (H, W, ...) that the convex hulls of the
    keypoint arrays ``point_sets`` (each (N, 2) px) cover, with a rim about them (an object's
    own pixels, as far as its keypoints show it)."""
    area = np.zeros(shape[:2], np.uint8)
    for points in point_sets:
        cv2.fillConvexPoly(area, cv2.convexHull(np.round(points).astype(np.int32)), 1)
    return cv2.dilate(area, _RIM)


def _label(regions: np.ndarray, point: tuple[float, float]) -> int:
    x = min(max(int(round(point[0])), 0), regions.shape[1] - 1)
    y = min(max(int(round(point[1])), 0), regions.shape[0] - 1)
    return int(regions[y, x])


def _spread(points: np.ndarray) -> float:
    """The radius (px) of keypoints (N, 2) about their centre."""
    return float(np.max(np.hypot(*(points - points.mean(axis=0)).T))) if len(points) else 0.0


def _same_object(a: MovedObject, b: MovedObject, rim: float) -> bool:
    """Two fits of one object (a symmetric one fits turned as well; one whose look others share
    in part fits onto them too): where they were lies within the larger keypoint spread. The
    nearer one, taken first, stands."""
    reach = max(_spread(a.keypoints_before), _spread(b.keypoints_before), rim)
    return bool(np.hypot(a.before[0] - b.before[0], a.before[1] - b.before[1]) <= reach)


def _same_place(a: MovedObject, b: MovedObject, rim: float) -> bool:
    """Whether the two fits put their objects in one place: where they are lies within the
    larger keypoint spread."""
    reach = max(_spread(a.keypoints_after), _spread(b.keypoints_after), rim)
    return bool(np.hypot(a.after[0] - b.after[0], a.after[1] - b.after[1]) <= reach)


def _within(operated: MovedObject, other: MovedObject, rim: float) -> bool:
    """Whether ``other``'s move lies where ``operated`` left or arrived: its centre or most of its
    keypoints, before or after, within the operated object's keypoint spread (and a rim) of its
    places."""
    for centre, points in ((operated.before, operated.keypoints_before), (operated.after, operated.keypoints_after)):
        reach = _spread(points) + rim
        if min(np.hypot(*np.subtract(centre, other.before)), np.hypot(*np.subtract(centre, other.after))) <= reach:
            return True
        for kept in (other.keypoints_before, other.keypoints_after):
            if np.mean(np.hypot(*(kept - np.asarray(centre)).T) <= reach) > 0.5:
                return True
    return False


def _placements(
    before: Features,
    after: Features,
    members: np.ndarray,
    free: np.ndarray,
    changed: np.ndarray,
    images: tuple[np.ndarray, np.ndarray],
    rules: SlipRules,
) -> list[tuple[float, MovedObject, np.ndarray, np.ndarray]]:
    """The moves of the objects whose pre keypoints are ``members`` (indices into ``before``):
    RANSAC similarities fitted one after the other on each keypoint's two nearest matches among
    ``after`` (only those indexed by ``free``; each fit's inlier pairs taken out before the
    next). A placement is an object's move when it moves its keypoints and most of them lie on
    ``changed`` pixels (H, W) both before and after (an object that moved left its place and
    arrived at another; the unchanged surroundings of a region match themselves) and the
    object's pixels moved by it match the post observation (``images``: pre, post) better than
    left where they were (:func:`_mismatch`). Each with its distance, the object and its inlier
    keypoint indices (pre, post)."""
    if len(members) < rules.min_inliers or len(free) < rules.min_inliers:
        return []
    pairs = cv2.BFMatcher(cv2.NORM_L2).knnMatch(before.descriptors[members], after.descriptors[free], k=2)
    source_index = np.array([members[m.queryIdx] for match in pairs for m in match], int)
    target_index = np.array([free[m.trainIdx] for match in pairs for m in match], int)
    found = []
    cv2.setRNGSeed(0)  # deterministic RANSAC
    for _ in range(rules.fits):
        if len(np.unique(source_index)) < rules.min_inliers:
            break
        source = before.keypoints[source_index, :2].reshape(-1, 1, 2)
        target = after.keypoints[target_index, :2].reshape(-1, 1, 2)
        model, inliers = cv2.estimateAffinePartial2D(
            source, target, method=cv2.RANSAC, ransacReprojThreshold=rules.reprojection
        )
        if model is None or inliers is None:
            break
        inliers = inliers.ravel().astype(bool)
        sources, targets = np.unique(source_index[inliers]), np.unique(target_index[inliers])
        if min(len(sources), len(targets)) < rules.min_inliers:
            break
        scale, turn = float(np.hypot(model[0, 0], model[1, 0])), float(np.arctan2(model[1, 0], model[0, 0]))
        centre = before.keypoints[sources, :2].mean(axis=0)
        moved_to = model[:, :2] @ centre + model[:, 2]
        shift = float(np.hypot(*(moved_to - centre)))
        still = shift < STILL_PX and abs(np.degrees(turn)) < STILL_DEG
        seen = _on(changed, before.keypoints[sources]) and _on(changed, after.keypoints[targets])
        if SCALE_RANGE[0] <= scale <= SCALE_RANGE[1] and not still and seen:
            obj = MovedObject(
                (float(centre[0]), float(centre[1])),
                (float(moved_to[0]), float(moved_to[1])),
                turn,
                before.keypoints[sources, :2].copy(),
                after.keypoints[targets, :2].copy(),
                model,
            )
            share = _mismatch(obj, *images)
            if share <= rules.explains:
                found.append((shift, replace(obj, mismatch=share), sources, targets))
        # The inlier pairs are this placement's; the same keypoints may still place their object
        # elsewhere (an identical object), which the nearest-first pairing decides.
        source_index, target_index = source_index[~inliers], target_index[~inliers]
    return found


def _mismatch(obj: MovedObject, pre: np.ndarray, post: np.ndarray) -> float:
    """Identification by matching: the mean grey difference between the object's pixels (the
    hull of its keypoints before) moved by its transform and the post observation there (H, W,
    3 both), as a share of their difference left where they were. A move explains its object
    when the share is at most :data:`EXPLAINS`: a fit that only lines up a few features of what
    something else covered or uncovered does not."""
    mask = np.zeros(pre.shape[:2], np.uint8)
    cv2.fillConvexPoly(mask, cv2.convexHull(np.round(obj.keypoints_before).astype(np.int32)), 1)
    grey_pre = cv2.cvtColor(pre, cv2.COLOR_RGB2GRAY).astype(np.float32)
    grey_post = cv2.cvtColor(post, cv2.COLOR_RGB2GRAY).astype(np.float32)
    size = (pre.shape[1], pre.shape[0])
    moved = cv2.warpAffine(grey_pre, obj.transform, size, flags=cv2.INTER_LINEAR)
    moved_mask = cv2.warpAffine(mask, obj.transform, size, flags=cv2.INTER_NEAREST) > 0
    if not moved_mask.any() or not mask.any():
        return 1.0
    fitted = float(np.mean(np.abs(moved - grey_post)[moved_mask]))
    left = float(np.mean(np.abs(grey_pre - grey_post)[mask > 0]))
    return fitted / max(left, 1e-6)


def _on(mask: np.ndarray, keypoints: np.ndarray) -> bool:
    """Whether most ``keypoints`` (N, >=2) lie on ``mask`` (H, W)."""
    xy = np.clip(np.round(keypoints[:, :2]).astype(int), 0, [mask.shape[1] - 1, mask.shape[0] - 1])
    return bool(np.mean(mask[xy[:, 1], xy[:, 0]] > 0) >= 0.5)
