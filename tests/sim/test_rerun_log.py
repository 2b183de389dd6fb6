"""A trial's rerun recording: read back with the SDK, the arm's chain and the hand's path on the
simulated clock, one step per caption, the images, state and plan at the step they were logged,
and a simulation that logging leaves alone."""

from __future__ import annotations

import numpy as np
import pytest

from vslsp.sim import LineWorld, SceneSpec
from vslsp.sim.rerun_log import ARM_EVERY, STEPS_PER_SECOND, RerunLog, merge
from vslsp.sim.scene import TABLE_Z

rerun_chunk = pytest.importorskip("rerun.chunk")

from helpers.rerun import rows  # noqa: E402 (once the SDK is known to be there)

REACH = np.array([0.3, -0.1, TABLE_Z + 0.05])


def _trial(recording: RerunLog | None) -> tuple:
    with LineWorld(SceneSpec.random(3)) as world:
        if recording is not None:
            recording.attach(world)
            recording.caption("the robot reaches over the cubes")
        assert world.robot is not None
        world.robot.move_hand(REACH[None, :])
        picture = world.observe("head").rgb
        if recording is not None:
            recording.caption("the robot looks")
            recording.observation("a look", picture, picture)
            recording.state(["(far orange)", "(not (far green))"])
            recording.plan(["pull orange", "pull green"])
            recording.cloud("capture", np.zeros((5, 3)))
            recording.close()
        return world.body_poses(), picture.shape


def test_a_logged_trial_reads_back_on_the_step_and_simulated_timelines(tmp_path):
    _, shape = _trial(RerunLog(tmp_path / "t.rrd", 7, "vslsp:test"))
    logged = rows(tmp_path / "t.rrd")
    assert {"/trial/7/arm", "/trial/7/hand_path", "/trial/7/narration", "/trial/7/camera/after"} <= set(logged)
    arm = logged["/trial/7/arm"]
    ticks = [row["sim_time"] for row in arm]
    assert len(arm) > 1 and ticks == sorted(ticks)
    assert np.allclose(np.diff(ticks) / 1e9, ARM_EVERY / STEPS_PER_SECOND)  # one reading every ARM_EVERY physics steps
    assert all(row["step"] == 1 for row in arm)  # the reach happened during the first step
    (image,) = logged["/trial/7/camera/after"]
    (state,) = logged["/trial/7/state"]
    (plan,) = logged["/trial/7/plan"]
    assert image["step"] == state["step"] == plan["step"] == 2
    assert state["TextDocument:text"] == ["(far orange)\n(not (far green))"]
    assert plan["TextDocument:text"] == ["1. pull orange\n2. pull green"]
    assert image["Image:format"][0]["width"] == shape[1]


def test_logging_leaves_the_simulation_alone(tmp_path):
    logged, _ = _trial(RerunLog(tmp_path / "t.rrd", 7, "vslsp:test"))
    alone, _ = _trial(None)
    assert logged == alone


def test_the_parts_of_a_run_merge_into_one_recording(tmp_path):
    parts = []
    for seed in (1, 2):
        recording = RerunLog(tmp_path / f"trial-{seed}.rrd", seed, "vslsp:run")
        recording.caption(f"trial {seed}")
        recording.close()
        parts.append(tmp_path / f"trial-{seed}.rrd")
    merge(parts, tmp_path / "run.rrd", "vslsp:run")
    (store,) = rerun_chunk.RrdReader(tmp_path / "run.rrd").recordings()
    assert store.recording_id == "vslsp:run"
    assert {"/trial/1/narration", "/trial/2/narration"} <= set(rows(tmp_path / "run.rrd"))
