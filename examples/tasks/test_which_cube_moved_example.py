"""The task-of-one's-own example (examples/tasks/which_cube_moved.py) runs as a user runs it:
registered, run by the common runner, every trial judged on the simulator's truth."""

from pathlib import Path

from helpers.examples import run_example

EXAMPLE = Path(__file__).with_name("which_cube_moved.py")


def test_the_example_task_runs_its_trials(capsys, monkeypatch):
    printed = run_example(EXAMPLE, ["2"], capsys, monkeypatch)
    assert "seed 0: ok" in printed and "seed 1: ok" in printed
    assert printed.strip().endswith("2/2 trials succeeded")
