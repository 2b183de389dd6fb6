"""The iCub experiments' execution faults (``--faults``), injected through the loop's hooks: a
skipped step and a cube put back are noticed by the monitor, and the fault log explains them."""

import pytest

from vslsp.experiments.icub_faults import Faults, FaultyStep, fault_log, fault_of
from vslsp.loop.monitor import StepResult, execute_step
from vslsp.loop.perception import perceive
from vslsp.sim import SceneSpec
from vslsp.symbolic import PlanResult
from vslsp.worlds.icub import IcubLineWorld


@pytest.mark.parametrize("fault", ["skip", "nudge"])
def test_a_faulty_step_is_noticed(library, fault):
    spec = SceneSpec.random(4, n_cubes=1, far=(True,))
    name = spec.cubes[0].name
    faults = Faults({0: fault})
    with IcubLineWorld.from_layout(spec) as world:
        state = perceive(world)
        assert faults.upcoming() == fault
        result, after = execute_step(world, library, "pull", name, state, False, faults.act)
        assert not result.ok
        assert result.observed_far is True and world.is_far(name)
        assert "expected (far" in result.error
        assert (result.trajectory is None) == (fault == "skip")  # a nudged step moved the hand
        # The step says which fault it carried, in the words the report uses.
        marked = faults.mark(0, result)
        assert fault_of(marked) == fault and marked.to_dict() == {**result.to_dict(), "fault": fault}
        assert (marked.expected, marked.observed) == (f"(not (far {name}))", f"(far {name})")
        assert faults.upcoming() is None and faults.mark(1, result) is result


def test_a_fault_drawn_past_the_first_plan_moves_to_its_last_step():
    faults = Faults({3: "skip"})
    faults.planned(PlanResult((("pull", ("red",)), ("pull", ("blue",))), "fast-downward", 0.0), 0)
    assert faults.schedule == {1: "skip"}
    faults.planned(PlanResult((("pull", ("red",)),), "fast-downward", 0.0), 2)  # a replan: the schedule stays
    assert faults.schedule == {1: "skip"}


def test_the_fault_log_explains_each_fault_and_what_followed_it():
    skipped = FaultyStep("pull", "green", False, True, False, "expected ...", fault="skip")
    again = StepResult("pull", "green", False, False, True, None)
    nudged = FaultyStep("push", "red", True, None, False, "expected ...", fault="nudge")
    vsl_skipped = FaultyStep("pull", "blue", False, True, False, "expected ...", fault="skip")
    vsl_again = StepResult("pull", "blue", False, False, True, None)
    steps = [skipped, again, nudged, vsl_skipped, vsl_again]
    log = fault_log(steps, {id(skipped), id(again), id(nudged)}, "gave up")
    assert [(e["step"], e["kind"]) for e in log] == [(1, "skip"), (3, "nudge"), (4, "skip")]
    assert log[0]["expected"] == "(not (far green))" and log[0]["observed"] == "(far green)"
    assert log[0]["recovery"] == "replanned: pull green"
    # The planned run's next step is VSL's, not a recovery of the planner's: none followed it.
    assert log[1]["observed"] == "red not seen" and log[1]["recovery"] == "none: gave up"
    assert log[2]["recovery"] == "VSL matched again: pull blue"
    assert fault_log([again], {id(again)}, "") == []
