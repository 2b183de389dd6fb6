"""The report's statistics against values worked out by hand or by the textbook formulas."""

import json

import pytest
from example_tasks import DiceBelowFive  # noqa: F401  (registers the example tasks)

from vslsp.tasks import get_task, run_trials, write_report
from vslsp.tasks.statistics import describe, pose_error, total_stages, wilson_interval


@pytest.mark.parametrize(
    ("successes", "trials", "expected"),
    [(0, 10, [0.0, 0.2775]), (10, 10, [0.7225, 1.0]), (5, 10, [0.2366, 0.7634]), (95, 100, [0.8882, 0.9785])],
)
def test_the_wilson_interval_matches_its_published_values(successes, trials, expected):
    assert wilson_interval(successes, trials) == pytest.approx(expected, abs=1e-4)


def test_pose_error_statistics_over_operations():
    summary = pose_error([(1.0, 0.5), (2.0, 1.5), (3.0, 1.0), (10.0, 2.0)])
    assert summary["operations"] == 4
    assert summary["mm"] == {"mean": 4.0, "sd": pytest.approx(4.082, abs=1e-3), "median": 2.5, "p95": 8.95}
    assert summary["deg"]["median"] == 1.25 and pose_error([]) is None
    assert describe([7.0])["sd"] == 0.0


def test_stage_totals_sum_the_trials():
    assert total_stages([{"perception": 1.0, "planning": 0.5, "execution": 2.0, "other": 0.25}] * 2) == {
        "perception": 2.0,
        "planning": 1.0,
        "execution": 4.0,
        "other": 0.5,
    }
    assert total_stages([None]) is None


def test_the_report_has_the_interval_and_every_trial_its_stage_times(tmp_path):
    task = get_task("dice-below-five")
    run = run_trials(task, range(3, 9))
    data = write_report(tmp_path, task, run)
    assert data["success_ci95"] == wilson_interval(data["successes"], 6)
    for record in json.loads((tmp_path / "report.json").read_text())["results"]:
        assert set(record["stages_s"]) == {"perception", "planning", "execution", "other"}
        assert round(sum(record["stages_s"].values()), 3) == record["time_s"]
    report = (tmp_path / "report.md").read_text()
    lo, hi = data["success_ci95"]
    assert f"({100 * lo:.1f}-{100 * hi:.1f} %)" in report and "Time by stage" in report
