"""The VSL-SP example (examples/icub/vslsp_end_to_end.py) runs as a user runs it: the learned
models, the demonstrated order planned, executed and checked in a new scene."""

from pathlib import Path

import pytest
from helpers.examples import run_example

EXAMPLE = Path(__file__).with_name("vslsp_end_to_end.py")


@pytest.mark.slow
def test_the_example_plans_and_executes_the_demonstrated_order(capsys, monkeypatch):
    printed = run_example(EXAMPLE, ["0"], capsys, monkeypatch)
    assert ":effect (and (not (far ?b))))" in printed  # pull's learned model
    assert "plan: pull orange, pull green, pull yellow; executed: orange, green, yellow" in printed
    assert printed.strip().endswith("succeeded")
