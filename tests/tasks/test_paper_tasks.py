"""The paper's VSL tasks through the task interface, on more seeds than their own tests: every
Panda task on a second seed (the Tower of Hanoi without the user's intervention), and the
house-roof simulation's adaptive frame against the fixed one over several seeds."""

from __future__ import annotations

import pytest

from vslsp.tasks import get_task, run_trials

pytestmark = pytest.mark.slow


@pytest.mark.parametrize(
    ("name", "seed"),
    [
        ("alphabet-ordering", 11),
        ("animal-puzzle", 12),
        ("tower-of-hanoi", 4),
        ("animals-vs-machines", 13),
        ("domino", 14),
    ],
)
def test_every_panda_task_succeeds_on_a_second_seed(name, seed):
    result = get_task(name).run_trial(seed)
    assert result.success, result.error
    robot = [op for op in result.operations if op["actor"] == "robot"]
    assert robot and all(op["diagnosis"] == "ok" for op in robot)
    if name == "tower-of-hanoi":
        assert result.details["variant"] == "" and len(robot) == 7  # no intervention: the robot makes all 7 moves


def test_the_adaptive_frame_succeeds_where_the_fixed_one_fails():
    run = run_trials(get_task("house-roof"), range(20, 24), workers=2)
    adaptive = [r.details["adaptive"]["success"] for r in run.results]
    fixed = [r.details["fixed"]["success"] for r in run.results]
    assert all(adaptive), [r.error for r in run.results]
    # ... where the fixed frame misplaces or loses a piece on some of these seeds (20, 21, 22:
    # why the frames adapt to the object's size)
    assert not all(fixed)
    lost = [op["diagnosis"] for r in run.results for op in r.details["fixed"]["operations"] if op["diagnosis"] != "ok"]
    assert lost and set(lost) <= {"wrong place", "no match"}
