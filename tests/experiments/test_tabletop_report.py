"""The tabletop tasks' trials and report: the summary counts the robot's operations and their
diagnoses (the benchmark's figure), and the command refuses bad input before any work."""

import pytest
from helpers.cli import vslsp
from helpers.records import without_times

from vslsp.errors import InputError
from vslsp.tasks import Run, TrialResult, get_task, run_one, run_trials, summary, write_report


def operation(actor: str, diagnosis: str, item: str = "A") -> dict:
    return {"operation": 1, "actor": actor, "item": item, "diagnosis": diagnosis}


def test_the_summary_rates_the_robots_operations_and_names_the_failures():
    trials = [
        TrialResult("domino", 0, True, None, 2.0, [operation("tutor", "ok"), operation("robot", "ok")]),
        TrialResult(
            "domino",
            1,
            False,
            "operation 1 (robot, B): grasp failed",
            4.0,
            [operation("tutor", "ok"), operation("robot", "grasp failed", "B")],
        ),
        TrialResult("domino", 2, False, "demonstration: no object was taken", 1.0, []),
    ]
    data = summary(get_task("domino"), Run(trials, [0, 1, 2]))
    assert (data["trials"], data["successes"], data["success_rate"]) == (3, 1, pytest.approx(1 / 3))
    assert (data["operations"], data["operations_ok"], data["operation_success_rate"]) == (2, 1, 0.5)
    assert data["diagnoses"] == {"grasp failed": 1, "ok": 1}  # the tutor's moves are not the robot's
    assert data["s_per_trial"] == pytest.approx(7.0 / 3, abs=0.01)
    assert [f["seed"] for f in data["failures"]] == [1, 2]
    assert "operation 1 (robot, B): grasp failed" in data["failures"][0]["error"]


def test_a_demonstration_that_failed_after_recording_slips_is_summarised():
    """A demonstration stopped at an operation it could not record keeps the operations recorded
    before (what moved in each, with detection on); they are the tutor's, with no actor."""
    slip = {"operation": 1, "moved": ["A", "B"], "operated": "A", "disturbed": ["B"], "slip": {"object": "B"}}
    trials = [
        TrialResult("domino", 0, True, None, 2.0, [operation("tutor", "ok"), operation("robot", "ok")]),
        TrialResult("domino", 1, False, "demonstration: features do not match", 1.0, [slip, {"operation": 2}]),
    ]
    data = summary(get_task("domino", tutor_slips=0.5), Run(trials, [0, 1]))
    assert (data["trials"], data["successes"], data["operations"], data["operations_ok"]) == (2, 1, 1, 1)
    assert "pose_error" not in data  # the robot's one operation recorded no pose error


def test_the_tower_of_hanoi_has_the_users_intervention_on_odd_seeds():
    assert (
        not get_task("tower-of-hanoi").for_seed(4).intervention and get_task("tower-of-hanoi").for_seed(5).intervention
    )
    assert get_task("tower-of-hanoi").for_seed(5).anchor_map == {"base-2": "base-3", "base-3": "base-2"}


def test_bad_input_is_refused_before_any_work(capsys):
    with pytest.raises(InputError, match="unknown experiment 'jigsaw'"):
        get_task("jigsaw")
    assert vslsp(capsys, "experiment", "domino", "--workers", "0")[0] == 2
    assert vslsp(capsys, "experiment", "domino", "--trials", "0")[0] == 2
    code, _, err = vslsp(capsys, "experiment", "tower-of-hanoi", "--faults")
    assert code == 2 and "--faults applies to the VSL-SP experiments" in err


@pytest.mark.slow
def test_a_run_keeps_its_first_trials_pictures_and_the_same_record(tmp_path):
    """The report draws the first trial from what that trial kept (no re-run of it): keeping its
    pictures leaves its record as a trial that keeps nothing has it."""
    task = get_task("animals-vs-machines")
    (kept,) = run_trials(task, [3]).results
    assert kept.artefacts is not None
    assert without_times(kept.to_dict()) == without_times(run_one(task, 3).to_dict())
    data = write_report(tmp_path, task, Run([kept], [3]))
    assert data["shown_trial"]["seed"] == 3 and (tmp_path / data["shown_trial"]["matches"]).stat().st_size > 1000
