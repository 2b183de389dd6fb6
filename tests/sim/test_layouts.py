"""The iCub line world's layouts: sides of the line that no seed can lay out are refused at once
with why (the row the hand's sweep bands need is longer than the stretch of the line in reach),
before the first trial of a task that declares them; every layout the sampler can place passes."""

import itertools

import pytest

from vslsp.errors import InputError
from vslsp.experiments.icub import IcubExperiment
from vslsp.sim.scene import LayoutImpossible, SceneSpec, check_layout
from vslsp.worlds.icub import line_layout

COLOURS = ("red", "green", "blue")


def test_three_cubes_near_the_robot_are_refused_at_once_with_why():
    with pytest.raises(LayoutImpossible) as refused:
        line_layout(7, COLOURS, (False, False, False))  # once: 50 seeds of 30,000 draws each, ~81 s
    message = str(refused.value)
    assert message.startswith("3 cubes, 3 on the robot's side of the line and 0 beyond it, do not fit")
    assert "they need 23.0 cm, and at most 21.5 cm of the line is in reach and in view" in message
    assert "no scene found" not in message


def test_four_cubes_fit_on_no_sides_and_the_message_names_the_least_crowded():
    with pytest.raises(LayoutImpossible, match="4 cubes, 2 on the robot's side of the line and 2 beyond it"):
        SceneSpec.random(3, n_cubes=4)


@pytest.mark.parametrize("far", [f for n in (2, 3) for f in itertools.product((False, True), repeat=n)], ids=str)
def test_the_rule_refuses_exactly_the_layouts_the_sampler_cannot_place(far):
    try:
        check_layout(far)
    except LayoutImpossible:
        assert far == (False, False, False)
        return
    spec = line_layout(11, COLOURS[: len(far)], far)  # the rule never refuses what the sampler places
    assert len(spec.cubes) == len(far)


def test_a_task_that_declares_an_impossible_layout_is_refused_before_its_first_trial():
    class ThreeNear(IcubExperiment):
        name = "three-near"
        paper_section = "a user's task"
        layouts = ((True, False), (False, False, False))

    with pytest.raises(InputError, match="3 cubes, 3 on the robot's side"):
        ThreeNear().check()
    ThreeNear.layouts = ((True, False), (True, True, True))
    ThreeNear().check()
