"""Fixtures of the symbolic tests: the paper's demonstrations (helpers: tests/helpers/symbolic.py)."""

import pytest
from helpers.symbolic import demonstration, scene, step

from vslsp.symbolic import Step


@pytest.fixture
def keep_all_near_demonstrations() -> list[list[Step]]:
    """The three demonstrations of "Keeping All Objects Near", giving the rules
    r_1^1 <green -> near> IF <orange far>, r_1^2 <orange -> near> IF <green near>,
    r_2^1 <green -> near> IF <orange near>, r_3^1 <orange -> near> IF <green far>."""
    return [
        demonstration(scene(green=True, orange=True), ("pull", "green"), ("pull", "orange")),
        demonstration(scene(green=True, orange=False), ("pull", "green")),
        demonstration(scene(green=True, orange=True), ("pull", "orange")),
    ]


@pytest.fixture
def pull_in_order_demonstration() -> list[Step]:
    """ "Pull All Objects in a Given Order": orange, then green, then yellow."""
    return demonstration(
        scene(orange=True, green=True, yellow=True), ("pull", "orange"), ("pull", "green"), ("pull", "yellow")
    )


@pytest.fixture
def skill_executions() -> list[Step]:
    """Executions of the push and pull skills observed on several blocks (Table 3's input),
    including one failed push (nothing changed) and one step with no recognised action."""
    return [
        step("push", "green", scene(green=False, red=True), green=True),
        step("pull", "red", scene(green=True, red=True), red=False),
        step("push", "blue", scene(blue=False, red=False), blue=True),
        step("pull", "blue", scene(blue=True, yellow=False), blue=False),
        step("push", "yellow", scene(yellow=True)),  # already far: the push changed nothing
        step(None, "red", scene(red=False)),
    ]


@pytest.fixture(scope="module")
def pull_in_order():
    """The shipped domain and the pull-in-order problem, read once per module."""
    from helpers.symbolic import PDDL

    from vslsp.symbolic import read_pddl

    return read_pddl(PDDL / "domain.pddl", PDDL / "pull-in-order.pddl")
