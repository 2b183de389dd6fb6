"""Tasks written as a user would (docs/tasks.md), registered for the framework's tests."""

from __future__ import annotations

import os
import time
from pathlib import Path

import numpy as np

from vslsp.tasks import System, Task, TrialResult, register
from vslsp.tasks.drawing import label


@register
class DiceBelowFive(Task):
    """The docs' example: a trial rolls a die from its seed and succeeds below five."""

    name = "dice-below-five"
    system = System.VSL
    paper_section = "an example task (docs/tasks.md)"
    description = "Rolls a die from the seed; succeeds when it shows less than five."

    def run_trial(self, seed: int, keep: bool = False) -> TrialResult:
        roll = int(np.random.default_rng(seed).integers(1, 7))
        image = np.full((60, 200, 3), 40 * roll, np.uint8) if keep else None
        return TrialResult(
            self.name,
            seed,
            roll < 5,
            None if roll < 5 else f"rolled {roll}",
            operations=[{"operation": 1, "roll": roll}],
            details={"roll": roll},
            artefacts=image,
        )

    def summary(self, results: list[TrialResult]) -> dict:
        return {"mean_roll": float(np.mean([r.details["roll"] for r in results]))}

    def figures(self, folder: Path, shown: TrialResult) -> dict:
        from vslsp.vision.image import write_image

        write_image(folder / "roll.png", label(shown.artefacts, f"rolled {shown.details['roll']}"))
        return {"roll": "roll.png"}


@register
class Troublesome(Task):
    """Trials that raise (seed 1), kill their worker once (seed 2: a flag file in
    $VSLSP_TEST_FLAGS marks the first attempt), or, for interrupts, succeed at once (seed 10) or
    wait to be interrupted (seeds > 10); with $VSLSP_TEST_MARKERS set, seeds >= 10 write
    '<seed>.running' there first, holding their process id."""

    name = "troublesome"
    system = System.VSL
    paper_section = "tests"

    def run_trial(self, seed: int, keep: bool = False) -> TrialResult:
        if seed == 1:
            raise RuntimeError("the gripper caught fire")
        if seed == 2:
            flag = Path(os.environ["VSLSP_TEST_FLAGS"]) / f"attempt-{seed}"
            if not flag.exists():
                flag.write_text("died")
                os._exit(3)
        if seed >= 10:
            if os.environ.get("VSLSP_TEST_MARKERS"):
                (Path(os.environ["VSLSP_TEST_MARKERS"]) / f"{seed}.running").write_text(str(os.getpid()))
            if seed > 10:
                time.sleep(600)  # until the test interrupts the run
        return TrialResult(self.name, seed, True)


@register
class CrashesOnOdd(Task):
    """The worker process running an odd seed's trial dies, on every attempt (as a crash or an
    out-of-memory kill would end it); even seeds succeed."""

    name = "crashes-on-odd"
    system = System.VSL
    paper_section = "tests"

    def run_trial(self, seed: int, keep: bool = False) -> TrialResult:
        if seed % 2:
            os._exit(3)
        return TrialResult(self.name, seed, True)

    def shown_seed(self, results: list[TrialResult]) -> int:
        # The report re-runs the trial it shows in the calling process: an even one, which lives.
        return next(r.seed for r in results if r.seed % 2 == 0)


@register
class WaitsForCtrlC(Task):
    """For the command line on Ray: seed 0 finishes at once (marker '0.done'), the others mark
    '<seed>.started' and wait to be interrupted. The marker folder comes from the environment
    ($VSLSP_TEST_MARKERS: the command passes no task options)."""

    name = "ray-test-waits"
    system = System.VSL
    paper_section = "tests"

    def run_trial(self, seed: int, keep: bool = False) -> TrialResult:
        folder = Path(os.environ["VSLSP_TEST_MARKERS"])
        if seed:
            (folder / f"{seed}.started").write_text("")
            time.sleep(600)  # until the test interrupts the run
        (folder / f"{seed}.done").write_text("")
        return TrialResult(self.name, seed, True)
