"""The Gymnasium example (examples/gym/vsl_policy.py) runs as a user runs it and reaches the goal."""

import runpy
import sys
from pathlib import Path

import pytest

EXAMPLE = Path(__file__).with_name("vsl_policy.py")


@pytest.mark.slow
def test_the_example_reaches_the_goal(capsys, monkeypatch):
    monkeypatch.setattr(sys, "argv", [str(EXAMPLE), "1"])
    runpy.run_path(str(EXAMPLE), run_name="__main__")
    printed = capsys.readouterr().out
    assert "picked D, reward 1.0" in printed
    assert printed.strip().endswith("return 1.0")
