"""A trial's wall time split by stage: nested stages charge the innermost, the parts add up."""

import time

import pytest

from vslsp import stages


def test_nested_stages_charge_the_innermost_and_the_parts_add_up_to_the_trial():
    stages.reset()
    start = time.perf_counter()
    with stages.stage("execution"):
        time.sleep(0.02)
        with stages.stage("perception"):  # a camera image during a motion is perception
            time.sleep(0.03)
    total = time.perf_counter() - start + 0.01
    parts = stages.split(total)
    assert set(parts) == {"perception", "planning", "execution", "other"}
    assert parts["perception"] >= 0.03 and parts["execution"] >= 0.02
    assert parts["planning"] == 0.0 and parts["other"] >= 0.0
    assert round(sum(parts.values()), 3) == round(total, 3)


def test_a_decorated_function_is_charged_to_its_stage_and_unknown_stages_are_refused():
    @stages.in_stage("planning")
    def plan() -> str:
        time.sleep(0.01)
        return "plan"

    stages.reset()
    assert plan() == "plan" and stages.split(1.0)["planning"] >= 0.01
    with pytest.raises(ValueError, match="unknown stage"):
        with stages.stage("dreaming"):
            pass
