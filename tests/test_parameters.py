"""The parameter objects of the algorithms' tuned rules: the defaults are the figures the
experiments have always run, a value out of its range is one clear InputError, a setting
``PREFIX.FIELD=VALUE`` is read as the field's type, and a rule passed in is the one applied."""

import dataclasses

import numpy as np
import pytest

from vslsp.errors import InputError
from vslsp.parameters import with_settings
from vslsp.vision.matching import MARGIN, MIN_SCORE, SCALE_RANGE, frame_sizes
from vslsp.vision.parameters import DEFAULT_FRAME_SEARCH, DEFAULT_OBJECT_FINDING, FrameSearch, ObjectFinding
from vslsp.vsl3d.grasping import GRASP_DEPTH, plan_grasp
from vslsp.vsl3d.parameters import DEFAULT_CLOUD_MATCHING, DEFAULT_GRASPING, CloudMatching, Grasping
from vslsp.vsl3d.vsl import CHANGE_THRESHOLD, MIN_CLUSTER_POINTS


def test_the_defaults_are_the_rules_the_experiments_run():
    assert (DEFAULT_FRAME_SEARCH.margin, DEFAULT_FRAME_SEARCH.min_score) == (MARGIN, MIN_SCORE) == (0.1, 0.5)
    assert DEFAULT_FRAME_SEARCH.scale_range == SCALE_RANGE == (0.67, 1.5)
    assert DEFAULT_FRAME_SEARCH.refit_turn == np.radians(4.0)
    assert (DEFAULT_OBJECT_FINDING.ratio, DEFAULT_OBJECT_FINDING.min_inliers, DEFAULT_OBJECT_FINDING.patch) == (
        0.8,
        4,
        128,
    )
    assert DEFAULT_OBJECT_FINDING.texture_share == 0.35
    assert (DEFAULT_CLOUD_MATCHING.confident_fitness, DEFAULT_CLOUD_MATCHING.upright_weight) == (0.75, 0.4)
    assert (CHANGE_THRESHOLD, MIN_CLUSTER_POINTS, DEFAULT_CLOUD_MATCHING.silhouette_px) == (0.01, 150, 1)
    assert DEFAULT_GRASPING.grasp_depth == GRASP_DEPTH == 0.03
    assert DEFAULT_GRASPING.grip_heights == (0.5,)


@pytest.mark.parametrize(
    "make, message",
    [
        (lambda: FrameSearch(margin=1.5), r"FrameSearch.margin is 1.5; it must lie in \[0.0, 1.0\]"),
        (lambda: FrameSearch(scale_range=(1.2, 1.5)), "low <= 1 <= high"),
        (lambda: FrameSearch(neighbours=2.5), "FrameSearch.neighbours is 2.5"),  # an int field takes ints
        (lambda: ObjectFinding(min_inliers=2), r"ObjectFinding.min_inliers is 2; it must lie in \[3, 1000\]"),
        (lambda: CloudMatching(turns=0), r"CloudMatching.turns is 0; it must lie in \[1, 360\]"),
        (lambda: Grasping(grip_heights=(0.5, 1.2)), r"Grasping.grip_heights is \(0.5, 1.2\)"),
        (lambda: Grasping(grip_heights=()), "grip_heights is empty"),
    ],
)
def test_a_value_out_of_its_range_is_refused(make, message):
    with pytest.raises(InputError, match=message):
        make()


def test_settings_are_read_as_the_fields_types():
    chosen = with_settings(
        {"cloud": DEFAULT_CLOUD_MATCHING, "grasping": DEFAULT_GRASPING},
        ["cloud.confident_fitness=0.8", "cloud.turns=6", "grasping.grip_heights=0.4,0.6"],
    )
    assert chosen["cloud"] == dataclasses.replace(DEFAULT_CLOUD_MATCHING, confident_fitness=0.8, turns=6)
    assert chosen["grasping"].grip_heights == (0.4, 0.6)
    assert with_settings({"cloud": DEFAULT_CLOUD_MATCHING}, []) == {"cloud": DEFAULT_CLOUD_MATCHING}


@pytest.mark.parametrize(
    "setting, message",
    [
        ("frame.margin=0.1", "PREFIX one of cloud"),
        ("cloud.margin=0.1", "cloud has no field 'margin'"),
        ("cloud.turns=six", "'six' is not a int"),
        ("cloud.turns", "not PREFIX.FIELD=VALUE"),
        ("cloud.turns=0", r"must lie in \[1, 360\]"),
    ],
)
def test_a_bad_setting_is_one_clear_error(setting, message):
    with pytest.raises(InputError, match=message):
        with_settings({"cloud": DEFAULT_CLOUD_MATCHING}, [setting])


def test_the_frame_search_passed_in_is_the_one_applied():
    assert frame_sizes(40, (360, 480, 3)) == [40, 60, 90, 135, 202, 304, 456, 480]
    assert frame_sizes(40, (360, 480, 3), FrameSearch(frame_growth=2.0)) == [40, 80, 160, 320, 480]
    assert frame_sizes(4, (360, 480, 3), FrameSearch(min_frame=30.0))[0] == 30


def test_the_grasping_rules_passed_in_are_the_ones_applied():
    # A box 4 cm square and 8 cm tall, sampled every 2 mm over its sides and top.
    grid = np.arange(0.0, 0.0401, 0.002)
    heights = np.arange(0.0, 0.0801, 0.002)
    sides = [np.array([(x, y, z) for x in grid for z in heights for y in (0.0, 0.04)])]
    sides.append(np.array([(x, y, z) for y in grid for z in heights for x in (0.0, 0.04)]))
    top = np.array([(x, y, 0.08) for x in grid for y in grid])
    points = np.vstack([*sides, top])
    half = plan_grasp(points, 0.04)
    low = plan_grasp(points, 0.04, parameters=Grasping(grip_heights=(0.25,)))
    assert half.point[2] == pytest.approx(0.04, abs=0.002)
    assert low.point[2] == pytest.approx(0.02, abs=0.002)
