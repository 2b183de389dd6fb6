"""Unit tests of the predicates in predicates.py (docs/grounding.md walks through this file).

The fixtures ``synthetic_pair``, ``rendered_pair`` and ``assert_grounds`` come from the vslsp
pytest plugin, which installing vslsp registers.
"""

from pathlib import Path

import pytest

from vslsp.grounding import load_predicates
from vslsp.grounding.testkit import Square
from vslsp.sim import CubeSpec, LandmarkSpec, SceneSpec

PREDICATES = load_predicates(Path(__file__).with_name("predicates.py"))


def test_pulling_green_across_the_line(synthetic_pair, assert_grounds):
    # The drawn table is 640x480 px; its line runs from (0, 300) to (640, 260); the robot is below.
    pair = synthetic_pair([Square("red", (150, 400)), Square("green", (450, 150))], move=(1, (430, 400)))
    assert_grounds(
        pair.pre,
        pair.post,
        predicates=PREDICATES,
        atoms_pre=[
            "(far green)",
            "(on-robot-side red)",
            "(right-half green)",
            "(warm red)",
            "(left-of red green)",
            "(in-front-of red green)",
        ],
        atoms_post=[
            "(on-robot-side red)",
            "(on-robot-side green)",
            "(right-half green)",
            "(warm red)",
            "(left-of red green)",
        ],
    )


def test_perception_agrees_with_the_truth_of_a_drawn_scene(synthetic_pair, assert_grounds):
    squares = [Square("red", (100, 420)), Square("blue", (250, 130)), Square("yellow", (520, 400), angle=30)]
    pair = synthetic_pair(squares, move=(1, (300, 370)), noise=6.0)
    truth_pre, truth_post = pair.atoms(PREDICATES)
    assert "(far blue)" in truth_pre and "(far blue)" not in truth_post
    assert_grounds(pair.pre, pair.post, predicates=PREDICATES, atoms_pre=truth_pre, atoms_post=truth_post)


def test_a_wrong_expectation_names_the_missing_and_unexpected_atoms(synthetic_pair, assert_grounds):
    pair = synthetic_pair([Square("red", (150, 400)), Square("green", (450, 150))], move=(1, (430, 400)))
    with pytest.raises(AssertionError, match=r"missing \(left-of green red\); unexpected \(left-of red green\)"):
        assert_grounds(
            pair.pre,
            pair.post,
            predicates=PREDICATES,
            atoms_post=[
                "(on-robot-side red)",
                "(on-robot-side green)",
                "(right-half green)",
                "(warm red)",
                "(left-of green red)",
            ],
        )


@pytest.mark.slow
def test_a_rendered_scene_agrees_with_the_simulators_truth(rendered_pair, assert_grounds):
    spec = SceneSpec(
        cubes=(CubeSpec("a", "red", 0.17, -0.02), CubeSpec("b", "green", 0.30, -0.12)), landmark=LandmarkSpec(x=0.23)
    )
    pair = rendered_pair(spec, move=("b", (0.17, -0.15)))  # the tutor pulls green to the robot's side
    truth_pre, truth_post = pair.atoms(PREDICATES)
    assert "(far green)" in truth_pre and "(on-robot-side green)" in truth_post
    assert_grounds(pair.pre, pair.post, predicates=PREDICATES, atoms_pre=truth_pre, atoms_post=truth_post)
