"""VSL's one matcher (findBestMatch with adaptive frames) on rendered house-and-roof worlds: the
compared search tells three identical bodies apart by what lies about them, a constraint that a
placement does not fit sends the search on to the next placement, the one-placement search
is the adaptive-frame match itself, and a candidate is ruled out on its place, not on a poor
RANSAC fit of it. Judged on the generator's ground truth."""

from dataclasses import replace

import numpy as np
import pytest

from vslsp.experiments.house_roof_trial import ObservationFeatures, demonstrate, pick_frame, place_search, reproduce
from vslsp.geometry.poses import compose
from vslsp.vision.features import extract_features
from vslsp.vision.matching import Match, NoMatch, find_best_match
from vslsp.vision.transform import decompose
from vslsp.vsl.matcher import Round, Search, frame_correlation, match_observation, refit
from vslsp.worlds.house_roof.board import SLOTS, HouseWorld


@pytest.fixture(scope="module")
def demo():
    return demonstrate(0)


def _third_place(demo):
    """Operation 3's pre-place observation, where it goes (below body 3), and a world in which
    the first two houses have their roofs and the third roof is in the hand."""
    op = demo.demonstration.operations[2]
    world = HouseWorld.random(7)
    for k in range(2):
        world = world.with_roof(k, compose(world.bodies[k], SLOTS["top"]))
    return op, world.with_roof(2, None)


def test_the_compared_search_grows_the_frame_until_the_free_house_stands_out(demo):
    op, world = _third_place(demo)
    seen = world.render()
    point = (op.pose_post.x, op.pose_post.y)
    adaptive = match_observation(op.pre_place, seen, point, op.object_size, place_search("adaptive", op.object_size))
    assert isinstance(adaptive, Match) and not adaptive.ambiguous and adaptive.candidates >= 2
    target = compose(world.bodies[2], SLOTS["below"])
    assert np.hypot(adaptive.x - target[0], adaptive.y - target[1]) < 6.0
    fixed = match_observation(op.pre_place, seen, point, op.object_size, place_search("fixed", op.object_size))
    assert isinstance(fixed, Match) and fixed.frame < adaptive.frame


def test_a_placement_that_does_not_fit_the_constraint_is_passed_over_for_the_next(demo):
    op, world = _third_place(demo)
    seen = world.render()
    point = (op.pose_post.x, op.pose_post.y)
    below = [compose(body, SLOTS["below"]) for body in world.bodies]
    search = Search.growing([int(2 * op.object_size)], tries=4, leave_out=op.object_size)
    first = match_observation(op.pre_place, seen, point, op.object_size, search)
    assert isinstance(first, Match)
    nearest = min(range(3), key=lambda k: np.hypot(first.x - below[k][0], first.y - below[k][1]))

    def elsewhere(match: Match) -> bool:
        return bool(np.hypot(match.x - first.x, match.y - first.y) > op.object_size)

    second = match_observation(op.pre_place, seen, point, op.object_size, search, fits=elsewhere)
    assert isinstance(second, Match)
    others = [k for k in range(3) if k != nearest]
    assert min(np.hypot(second.x - below[k][0], second.y - below[k][1]) for k in others) < 6.0
    nowhere = match_observation(op.pre_place, seen, point, op.object_size, search, fits=lambda match: False)
    assert isinstance(nowhere, NoMatch) and not nowhere


def test_the_one_placement_search_is_the_adaptive_frame_match_itself(demo):
    op = demo.demonstration.operations[0]
    seen = HouseWorld.random(7).render()
    point, frames = (op.pose_pre.x, op.pose_pre.y), [pick_frame(op.object_size)]
    features = extract_features(op.pre_observation)
    ours = match_observation(op.pre_observation, seen, point, op.object_size, Search.growing(frames), features)
    theirs = find_best_match(op.pre_observation, seen, point, op.object_size, frames, features)
    assert isinstance(ours, Match) and isinstance(theirs, Match)
    fields = ("x", "y", "theta", "score", "frame", "ambiguous", "candidates")
    assert [getattr(ours, f) for f in fields] == [getattr(theirs, f) for f in fields]
    assert Search.compared([100, 150], 4).rounds == (Round((100,), 4, 50.0), Round((150,), 1, 75.0))


def test_a_poor_fit_is_refitted_to_its_copy(demo):
    op, world = _third_place(demo)
    seen = world.render()
    point = (op.pose_post.x, op.pose_post.y)
    good = match_observation(op.pre_place, seen, point, op.object_size, place_search("adaptive", op.object_size))
    assert isinstance(good, Match)
    # The same copy fitted as RANSAC may fit it on two features: a fifth too large, 5 px and 4 degrees off.
    c, s = 1.2 * np.cos(0.07), 1.2 * np.sin(0.07)
    off = np.array(
        [[c, -s, good.x + 5.0 - c * good.x + s * good.y], [s, c, good.y - s * good.x - c * good.y], [0, 0, 1]]
    )
    transform = off @ good.transform
    poor = replace(good, transform=transform, decomposition=decompose(transform))
    size = place_search("fixed", op.object_size).compare[0]
    before = frame_correlation(op.pre_place, seen, point, size, poor.transform)
    fitted = refit(op.pre_place, seen, point, size, poor)
    assert fitted.score > before + 0.2 and fitted.score > good.score - 0.02
    assert np.hypot(fitted.x - good.x, fitted.y - good.y) < 1.5
    assert abs(fitted.theta - good.theta) < np.radians(1.0)
    assert np.sqrt(np.linalg.det(fitted.transform[:2, :2])) == pytest.approx(1.0)
    # A degenerate fit (RANSAC collapsed the frame) has no pose to start from: it stays as it is.
    collapsed = replace(good, transform=np.array([[0.0, 0.0, good.x], [0.0, 0.0, good.y], [0.0, 0.0, 1.0]]))
    assert refit(op.pre_place, seen, point, size, collapsed) is collapsed


def test_a_frame_too_small_to_see_the_roofs_does_not_decide_on_a_poor_fit():
    # Trial 880008: at the first pre-place frame of operation 3 (the bottom of a body, no room
    # for its top) the right body's copy was fitted on two features at 1.22 times the scale and
    # lost by 0.28 to a house that already had its roof; re-fitted it ties, and the frame grows
    # until the missing roof is in view.
    from vslsp.experiments.seeds import reproduction_seed

    demo = demonstrate(880008)
    world = HouseWorld.random(reproduction_seed(880008))
    reproduction = reproduce(demo, world, "adaptive", ObservationFeatures(demo))
    assert [op.diagnosis for op in reproduction.operations] == ["ok", "ok", "ok"] and reproduction.success
    third = reproduction.operations[2]
    assert third.slot is not None and third.slot[:2] == (1, "below")
    assert (
        third.place is not None
        and third.place.frame > place_search("fixed", demo.demonstration.operations[2].object_size).compare[0]
    )


def _placing(seed: int, placed: tuple[tuple[int, int], ...], lifted: int):
    """Trial ``seed``'s reproduction world with roof r on top of body b for each (r, b) in
    ``placed`` (the operations done so far) and roof ``lifted`` in the hand."""
    from vslsp.experiments.seeds import reproduction_seed

    world = HouseWorld.random(reproduction_seed(seed))
    for roof, body in placed:
        world = world.with_roof(roof, compose(world.bodies[body], SLOTS["top"]))
    return world.with_roof(lifted, None)


@pytest.mark.parametrize(
    ("seed", "placed", "lifted", "free"),
    [
        # Operation 3: the two finished houses tie at every frame, and the free body's copy,
        # fitted on a few features at three quarters of the scale, trails them by 0.5.
        (881011, ((0, 0), (2, 1)), 1, 2),
        (881187, ((1, 2), (0, 0)), 2, 1),
    ],
)
def test_a_poor_fit_is_refitted_before_it_is_ruled_out_even_when_no_candidate_stands_out(seed, placed, lifted, free):
    demo = demonstrate(seed)
    op = demo.demonstration.operations[2]
    world = _placing(seed, placed, lifted)
    search = place_search("adaptive", op.object_size)
    match = match_observation(
        demo.pre_place[2], world.render(), (op.pose_post.x, op.pose_post.y), op.object_size, search
    )
    assert isinstance(match, Match) and not match.ambiguous and match.frame > search.compare[0]
    target = compose(world.bodies[free], SLOTS["below"])
    assert np.hypot(match.x - target[0], match.y - target[1]) < 6.0


def test_a_place_a_smaller_frame_ruled_out_does_not_come_back_at_a_larger_one():
    # Operation 2 with one house finished: the smaller frames see its roof and rule it out by
    # 0.19; the largest frame sees mostly the rest of the board, where it ties with the free ones.
    seed = 881120
    demo = demonstrate(seed)
    op = demo.demonstration.operations[1]
    world = _placing(seed, ((0, 0),), 2)
    point = (op.pose_post.x, op.pose_post.y)
    match = match_observation(
        demo.pre_place[1], world.render(), point, op.object_size, place_search("adaptive", op.object_size)
    )
    assert isinstance(match, Match)
    free = [compose(world.bodies[k], SLOTS["top"]) for k in (1, 2)]
    assert min(np.hypot(match.x - x, match.y - y) for x, y, _ in free) < 6.0  # either free body will do


def test_a_match_taken_on_a_poor_fit_is_refitted_before_it_is_taken():
    # Trial 882692, operation 3: the finished houses' copies were fitted degenerate (scale 0),
    # so no comparison re-fitted anything, and the free body's copy, fitted at 0.96 scale with
    # a correlation of 0.79 at the first frame, put the roof 6 degrees off its slot.
    from vslsp.experiments.seeds import reproduction_seed
    from vslsp.worlds.house_roof.board import ANGLE_TOLERANCE

    seed = 882692
    demo = demonstrate(seed)
    reproduction = reproduce(demo, HouseWorld.random(reproduction_seed(seed)), "adaptive", ObservationFeatures(demo))
    third = reproduction.operations[2]
    assert third.diagnosis == "ok" and reproduction.success
    assert third.slot is not None and third.slot[:2] == (1, "below") and third.slot[3] < ANGLE_TOLERANCE / 3
    assert third.place is not None and third.place.score > 0.9 and not third.place.ambiguous


def test_a_frame_grown_past_what_the_worlds_share_does_not_overturn_the_smaller_frames():
    # Trial 882695, operation 3: the free body led the finished houses by 0.094 (just short of
    # MARGIN) at the second and third frames, its correlation falling 0.99, 0.94 as the frame
    # took in more of the board; at the largest frame (0.70 against their 0.85) it lost, and an
    # occupied body was taken as unique. That frame's best fell MARGIN below the best reached:
    # the smaller frames' leader is taken, flagged ambiguous.
    seed = 882695
    demo = demonstrate(seed)
    op = demo.demonstration.operations[2]
    world = _placing(seed, ((0, 1), (1, 0)), 2)
    search = place_search("adaptive", op.object_size)
    match = match_observation(
        demo.pre_place[2], world.render(), (op.pose_post.x, op.pose_post.y), op.object_size, search
    )
    assert isinstance(match, Match) and match.ambiguous and search.compare[0] < match.frame < search.compare[-1]
    target = compose(world.bodies[2], SLOTS["below"])
    assert np.hypot(match.x - target[0], match.y - target[1]) < 6.0


def test_a_pick_fitted_far_turned_is_refitted_all_round():
    # Trial 883153, operation 3: RANSAC fitted the roof to pick 135 degrees off (0.75 at the
    # pick frame; the copy's pose correlates 0.96), which a local re-fit cannot reach, and the
    # roof landed on the right slot that far turned. Re-fitted from turns all round its place.
    from vslsp.experiments.house_roof_trial import PICK_TURNS
    from vslsp.experiments.seeds import reproduction_seed

    seed = 883153
    demo = demonstrate(seed)
    world = HouseWorld.random(reproduction_seed(seed))
    reproduction = reproduce(demo, world, "adaptive", ObservationFeatures(demo))
    assert [op.diagnosis for op in reproduction.operations] == ["ok", "ok", "ok"] and reproduction.success
    # The same pick, found in the world before operation 3, with and without the turns.
    for op in reproduction.operations[:2]:
        assert op.grasped is not None and op.landed is not None
        world = world.with_roof(op.grasped, op.landed)
    recorded = demo.demonstration.operations[2]
    point, frames = (recorded.pose_pre.x, recorded.pose_pre.y), [pick_frame(recorded.object_size)]
    args = (recorded.pre_observation, world.render(), point, recorded.object_size)
    poor = match_observation(*args, Search.growing(frames))
    good = match_observation(*args, Search.growing(frames, turns=PICK_TURNS))
    assert isinstance(poor, Match) and isinstance(good, Match) and good.score > poor.score + 0.1
    roof = world.roofs[0]
    assert roof is not None and np.hypot(good.x - roof[0], good.y - roof[1]) < 3.0
    turn = np.angle(np.exp(1j * (good.theta - (roof[2] - recorded.pose_pre.theta))))
    assert abs(turn) < np.radians(4.0)  # the demonstration's recorded turn is a measurement


def test_a_pick_fitted_degenerate_is_refitted_from_its_place():
    # Trial 884247, operation 1: RANSAC collapsed the pick frame to a point (a zero matrix), the
    # zero matrix was read as no turn, and the roof, put on a free body, landed 46 degrees off
    # its slot. A fit without a pose keeps its place and is re-fitted all round from there.
    from vslsp.experiments.house_roof_trial import PICK_TURNS
    from vslsp.experiments.seeds import reproduction_seed
    from vslsp.worlds.house_roof.board import ANGLE_TOLERANCE

    seed = 884247
    demo = demonstrate(seed)
    world = HouseWorld.random(reproduction_seed(seed))
    recorded = demo.demonstration.operations[0]
    point, frames = (recorded.pose_pre.x, recorded.pose_pre.y), [pick_frame(recorded.object_size)]
    args = (recorded.pre_observation, world.render(), point, recorded.object_size)
    fit = match_observation(*args, Search.growing(frames))
    assert isinstance(fit, Match) and abs(np.linalg.det(fit.transform[:2, :2])) < 1e-6  # the case pinned
    good = match_observation(*args, Search.growing(frames, turns=PICK_TURNS))
    assert isinstance(good, Match) and good.score > 0.9
    roof = world.roofs[world.roof_at((good.x, good.y))]
    assert roof is not None and np.hypot(good.x - roof[0], good.y - roof[1]) < 3.0
    reproduction = reproduce(demo, world, "adaptive", ObservationFeatures(demo))
    assert [op.diagnosis for op in reproduction.operations] == ["ok", "ok", "ok"] and reproduction.success
    first = reproduction.operations[0]
    assert first.pick is not None and abs(first.pick.theta - good.theta) < 1e-9
    assert first.slot is not None and first.slot[3] < ANGLE_TOLERANCE / 3  # it was 46 degrees off
