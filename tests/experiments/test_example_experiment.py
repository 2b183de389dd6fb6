"""docs/tasks.md's worked example: a new experiment on an existing world is one module, which
registers itself and runs through ``vslsp experiment`` with the common report."""

import json
import re
from importlib.metadata import entry_points
from pathlib import Path

import pytest
from example_experiment import TwoLettersInARow
from helpers.cli import REPO, vslsp

from vslsp.tasks import list_tasks


def test_the_docs_show_the_example_module_as_it_is():
    text = (REPO / "docs" / "tasks.md").read_text()
    shown = re.search(r"```python\n(.*?)```", text.split("## A new experiment on an existing world")[1], re.S)
    assert shown is not None
    source = (Path(__file__).parent / "example_experiment.py").read_text()
    assert shown.group(1) == source


def test_the_example_registers_itself_beside_the_papers_experiments():
    assert TwoLettersInARow in list_tasks()
    declared = [entry.module for entry in entry_points(group="vslsp.tasks")]
    assert all(module.startswith("vslsp.experiments.") for module in declared)  # the paper's own only


@pytest.mark.slow
def test_the_example_runs_through_the_command_line_and_reaches_its_goal(tmp_path, capsys):
    code, out, _ = vslsp(
        capsys, "experiment", "two-letters-in-a-row", "--trials", "1", "--seed", "3", "--json", "--out", tmp_path
    )
    data = json.loads(out)
    assert code == 0 and data["successes"] == 1, data["results"][0]["error"]
    record = data["results"][0]
    assert [op["item"] for op in record["operations"]] == ["B", "A"]
    assert all(op["diagnosis"] == "ok" for op in record["operations"])
    assert (tmp_path / "images" / "matches.png").exists()
