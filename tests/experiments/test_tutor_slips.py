"""--tutor-slips in VSL's 2-D experiments (issue 30): with the tutor slipping in every
operation, a trial succeeds with the slip detection on; the report names each operation's moved,
operated and disturbed objects beside the tutor's slip; the paper's VSL (detection off) fails
the same house-roof trial; without the option the records carry none of it."""

from __future__ import annotations

import pytest

from vslsp.tasks import get_task

pytestmark = pytest.mark.slow


def slipped(operations: list[dict]) -> list[dict]:
    return [op for op in operations if "slip" in op]


def test_house_roof_succeeds_with_a_slip_in_every_operation_only_with_the_detection():
    on = get_task("house-roof", tutor_slips=1.0, slip_detection=True).run_trial(0)
    assert on.success, on.error
    assert slipped(on.operations)  # the tutor did slip, and each slip was told from the operation
    for op in slipped(on.operations):
        assert op["disturbed"] == [op["slip"]["object"]]
        assert op["operated"] == f"roof-{op['operation'] - 1}"
        assert op["moved"] == [op["operated"], *op["disturbed"]]
    off = get_task("house-roof", tutor_slips=1.0, slip_detection=False).run_trial(0)
    assert not off.success and off.failure_cause == "demonstration"  # the paper's VSL takes both for one
    assert "operated" not in off.operations[0] and "slip" in off.operations[0]


def test_a_panda_task_succeeds_with_a_slip_in_every_operation():
    result = get_task("alphabet-ordering", tutor_slips=1.0, slip_detection=True).run_trial(0)
    assert result.success, result.error
    assert len(slipped(result.operations)) >= 2
    for op in result.operations:
        assert op["operated"] == op["item"]
        if "slip" in op:
            assert op["disturbed"] == [op["slip"]["object"]]
        else:
            assert op["disturbed"] == []


def test_without_the_option_the_records_carry_no_slip_fields():
    plain = get_task("house-roof").run_trial(5)
    assert plain.operations is None and "tutor_slips" not in get_task("house-roof").summary([plain])
