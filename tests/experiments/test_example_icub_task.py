"""The iCub task of docs/tasks.md (examples/icub/pull_two.py), a user's file run through
`--tasks` with the public hooks, in two workers: it learns, plans and executes, and the report's
VSL-SP column reads its documented field; a task that declares a layout no table can hold is
refused before its first trial."""

import json
import textwrap

import pytest
from helpers.cli import REPO, vslsp_process

EXAMPLE = REPO / "examples" / "icub" / "pull_two.py"


@pytest.mark.slow
def test_the_documented_icub_task_runs_from_its_file_in_two_workers(tmp_path):
    done = vslsp_process(
        "experiment", "--tasks", EXAMPLE, "pull-two", "--trials", "2", "--workers", "2", "--json", "--out", tmp_path
    )
    assert done.returncode == 0, done.stderr
    data = json.loads(done.stdout)
    assert data["successes"] == 2 and all(r["plan_length"] == 2 for r in data["results"])
    assert all(r["final_far"] == {"green": False, "orange": False} for r in data["results"])
    rows = [line for line in (tmp_path / "report.md").read_text().splitlines() if line.startswith("| 0 |")]
    assert rows and rows[0].endswith("| ok | - | ok |")  # VSL-SP from vsl_sp_success; no VSL reproduction


def test_an_icub_task_with_an_impossible_layout_is_refused_before_its_first_trial(tmp_path):
    (tmp_path / "three_near.py").write_text(
        textwrap.dedent("""
        from vslsp.experiments.icub import IcubExperiment
        from vslsp.tasks import register


        @register
        class ThreeNear(IcubExperiment):
            name = "three-near"
            paper_section = "a user's task"
            layouts = ((False, False, False),)
    """)
    )
    args = ("experiment", "--tasks", tmp_path / "three_near.py", "three-near", "--json", "--out", tmp_path / "out")
    done = vslsp_process(*args)
    assert done.returncode == 2 and not (tmp_path / "out").exists()
    assert json.loads(done.stdout)["error"].startswith("3 cubes, 3 on the robot's side of the line and 0 beyond it")
