"""Tasks for the interrupt and output tests (registered when imported; the command under test
runs as a program that imports this module first: :func:`helpers.processes.command`).

Each trial leaves marker files in ``$VSLSP_TEST_MARKERS`` so that a test waits on events
(a trial started, the figures started, a result in the driver), never on the clock.
"""

from __future__ import annotations

import os
import time
from pathlib import Path

import numpy as np

from helpers.events import became_true
from vslsp.tasks import System, Task, TrialResult, register


def _mark(name: str) -> None:
    (Path(os.environ["VSLSP_TEST_MARKERS"]) / name).write_text(str(os.getpid()))


def _wait_for(name: str) -> None:
    became_true((Path(os.environ["VSLSP_TEST_MARKERS"]) / name).exists)


@register
class WaitsAfterTheFirst(Task):
    """Seed 0 finishes at once; seed 1, once seed 0's result is in the driver ('0.reported',
    written there), marks ``waiting-1`` and waits to be interrupted; later seeds do the same."""

    name = "test-waits-after-the-first"
    system = System.VSL
    paper_section = "tests"

    def run_trial(self, seed: int, keep: bool = False) -> TrialResult:
        if seed == 0:
            return TrialResult(self.name, seed, True)
        _wait_for("0.reported")
        _mark(f"waiting-{seed}")
        time.sleep(600)
        return TrialResult(self.name, seed, True)


@register
class SlowFigures(Task):
    """Trials that finish at once, and figures that mark ``figures`` and wait to be interrupted."""

    name = "test-slow-figures"
    system = System.VSL
    paper_section = "tests"

    def run_trial(self, seed: int, keep: bool = False) -> TrialResult:
        return TrialResult(self.name, seed, True, artefacts=np.zeros((8, 8, 3), np.uint8) if keep else None)

    def figures(self, folder: Path, shown: TrialResult) -> dict:
        _mark("figures")
        time.sleep(600)
        return {}


@register
class Plans(Task):
    """A trial that plans the problem that makes Fast Downward grow (tests/data/limits), under a
    memory limit small enough for a test machine."""

    name = "test-plans"
    system = System.VSL_SP
    paper_section = "tests"

    def run_trial(self, seed: int, keep: bool = False) -> TrialResult:
        from vslsp.symbolic import read_pddl, solve

        root = Path(__file__).resolve().parents[2]
        domain, problem = read_pddl(
            root / "pddl" / "domain.pddl", root / "tests" / "data" / "limits" / "forall-or.pddl"
        )
        assert problem is not None
        solve(domain, problem, timeout=600, memory_mb=700)
        return TrialResult(self.name, seed, True)


@register
class Quick(Task):
    """Trials that succeed at once; a figure of noise (about 120 kB as PNG) for the shown one."""

    name = "test-quick"
    system = System.VSL
    paper_section = "tests"

    def run_trial(self, seed: int, keep: bool = False) -> TrialResult:
        return TrialResult(self.name, seed, True, artefacts=seed if keep else None)

    def figures(self, folder: Path, shown: TrialResult) -> dict:
        from vslsp.vision.image import write_image

        noise = np.random.default_rng(shown.seed).integers(0, 256, (200, 200, 3), dtype=np.uint8)
        write_image(folder / "noise.png", noise)
        return {"noise": "noise.png"}
