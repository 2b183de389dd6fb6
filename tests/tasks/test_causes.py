"""The report's failure causes come from typed fields (vslsp.tasks.base.TrialResult.failure_cause,
vslsp.errors.TaskFailed.cause), never from the text of a message; the causes of the registered
tasks are the short names the reports have always shown."""

from __future__ import annotations

import json
import pickle

import pytest

from vslsp.errors import GroundingFailed, TaskFailed
from vslsp.experiments.house_roof import _failure as house_roof_failure
from vslsp.experiments.tabletop import _failure as tabletop_failure
from vslsp.outcomes import Diagnosis
from vslsp.symbolic import NoPlan, PlanStatus, Unsolvable
from vslsp.tasks import TrialResult, TrialStatus
from vslsp.tasks.trial import run_one


def test_a_failed_trial_is_tallied_by_its_typed_cause_not_by_its_message():
    results = [
        TrialResult(
            "t", 1, False, "no plan: the planner's time limit of 1 s reached", failure_cause="planner time limit"
        ),
        TrialResult("t", 2, False, "ray: a: b", failure_cause="ray"),
        TrialResult("t", 3, False, "rolled 6"),  # a task that names no cause: its error is the cause
        TrialResult("t", 4, False),
        TrialResult("t", 5, True, failure_cause="ignored"),
    ]
    assert [r.cause for r in results] == ["planner time limit", "ray", "rolled 6", "goal not reached", "ok"]
    assert "failure_cause" not in results[0].to_dict()  # the records are as they were


def test_a_task_failure_carries_its_cause_and_keeps_it_across_processes():
    failure = TaskFailed("exploring push on green: the cube did not move", cause="exploring push on green")
    assert str(failure) == "exploring push on green: the cube did not move"
    assert TaskFailed("the robot sees no far object").cause == "the robot sees no far object"
    for error in (
        failure,
        NoPlan("the planner's time limit of 1 s reached", PlanStatus.TIMEOUT),
        Unsolvable("the goal cannot be reached"),
        GroundingFailed("nothing moved"),
    ):
        again = pickle.loads(pickle.dumps(error))
        assert (type(again), str(again), again.cause) == (type(error), str(error), error.cause)
        assert getattr(again, "status", None) == getattr(error, "status", None)
    assert NoPlan("x", PlanStatus.TIMEOUT).cause == "planner time limit"
    assert NoPlan("x", PlanStatus.MEMOUT).cause == "planner memory limit"
    assert NoPlan("x", PlanStatus.UNSOLVABLE_INCOMPLETELY).cause == Unsolvable("x").cause == "no plan"


def test_an_exception_in_a_trial_is_tallied_by_its_type():
    class Broken:
        name = "broken"

        def run_trial(self, seed: int, keep: bool = False) -> TrialResult:
            raise ValueError("a: b: c")

    result = run_one(Broken(), 3)  # type: ignore[arg-type]
    assert result.error is not None and result.error.startswith("ValueError: a: b: c (at ")
    assert result.cause == "ValueError"
    assert result.status is TrialStatus.RAISED and result.to_dict()["status"] == "raised"


def test_a_trial_status_agrees_with_its_success():
    solved, failed = TrialResult("t", 1, True), TrialResult("t", 2, False, "rolled 6")
    assert (solved.status, failed.status) == (TrialStatus.SOLVED, TrialStatus.FAILED)
    lost = TrialResult("t", 3, False, "worker died", failure_cause="worker died", status=TrialStatus.LOST)
    # the record keeps its keys (success, error) and adds the status beside them
    assert lost.to_dict() == {
        "experiment": "t",
        "seed": 3,
        "success": False,
        "status": "lost",
        "error": "worker died",
        "time_s": 0.0,
        "cpu_s": 0.0,
    }
    assert pickle.loads(pickle.dumps(lost)).status is TrialStatus.LOST
    assert lost.without_artefacts().status is TrialStatus.LOST
    with pytest.raises(ValueError, match="status solved cannot have success=False"):
        TrialResult("t", 4, False, status=TrialStatus.SOLVED)
    with pytest.raises(ValueError, match="status raised cannot have success=True"):
        TrialResult("t", 5, True, status=TrialStatus.RAISED)


def test_the_operation_tasks_name_the_first_failed_operation():
    operations = [
        {"operation": 1, "actor": "tutor", "item": "A", "diagnosis": "ok"},
        {"operation": 2, "actor": "robot", "item": "B", "diagnosis": "grasp failed"},
        {"operation": 3, "actor": "robot", "item": "C", "diagnosis": "misplaced"},
    ]
    error, cause = tabletop_failure(operations)
    assert error == "operation 2 (robot, B): grasp failed; operation 3 (robot, C): misplaced"
    assert cause == "operation 2 (robot, B)"
    assert tabletop_failure(operations[:1]) == ("goal not reached", "goal not reached")
    adaptive = {"operations": [{"diagnosis": "ok"}, {"diagnosis": "wrong place"}, {"diagnosis": "no match"}]}
    assert house_roof_failure(adaptive) == ("operation 2: wrong place; operation 3: no match", "operation 2")


def test_a_diagnosis_is_typed_and_written_as_the_same_string():
    record = {"diagnosis": Diagnosis.GRASP_FAILED, "diagnoses": {Diagnosis.OK: 2}}
    assert json.dumps(record) == '{"diagnosis": "grasp failed", "diagnoses": {"ok": 2}}'
    assert (
        f"{Diagnosis.NO_MATCH}" == str(Diagnosis.NO_MATCH) == "no match"
        and Diagnosis("misplaced") is Diagnosis.MISPLACED
    )
