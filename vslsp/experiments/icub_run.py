"""The state of one trial of the iCub experiments while it runs: what it found, what it keeps
for the report, the worlds it runs in (filmed with ``--video``: :mod:`vslsp.sim.video`, logged
with ``--rerun``: :mod:`vslsp.sim.rerun_log`) and their narration. The trial's record is a
:class:`~vslsp.tasks.TrialResult` built from it
(:meth:`vslsp.experiments.icub.IcubExperiment.run_trial`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from vslsp.experiments.icub_faults import FAULT_WHAT, Faults
from vslsp.loop.monitor import StepResult
from vslsp.loop.pipeline import Execution
from vslsp.sim import LineWorld, SceneSpec
from vslsp.sim.rerun_log import RerunLog
from vslsp.sim.video import SceneVideo
from vslsp.symbolic import Domain, LearnedTask
from vslsp.worlds.icub import IcubLineWorld


@dataclass
class IcubRun:
    """One trial as it runs: its outcome, its record's fields (``details``), and what the report
    shows (the artefacts of a kept trial)."""

    seed: int
    success: bool = False
    error: str | None = None
    cause: str | None = None  # the failure's short cause for the report's tally (None: the error is its own)
    details: dict = field(default_factory=dict)
    replans: int = 0
    failed_steps: int = 0
    # Artefacts for the report: (title, pre, post, grounding or None, the executed step or None),
    # PDDL, trajectories.
    observations: list = field(default_factory=list, repr=False)
    domain: Domain | None = field(default=None, repr=False)
    task: LearnedTask | None = field(default=None, repr=False)
    executions: list[Execution] = field(default_factory=list, repr=False)
    steps: list[StepResult] = field(default_factory=list, repr=False)
    gui: bool = field(default=False, repr=False)
    on_stage: object = field(default=None, repr=False, compare=False)
    predicates: tuple = field(default=(), repr=False, compare=False)  # the user's, grounded at every step
    video: SceneVideo | None = field(default=None, repr=False, compare=False)  # with --video
    recording: RerunLog | None = field(default=None, repr=False, compare=False)  # with --rerun
    # With --tutor-slips or --slip-detection: the tutor's slips, their detection, their records
    # (vslsp.experiments.icub_slips.Watcher); None: the tutor never slips, today's path.
    watcher: Any = field(default=None, repr=False, compare=False)
    # With --faults: the faults scheduled in the trial's execution (what play's ``faults`` is).
    faults: Faults = field(default_factory=Faults, repr=False, compare=False)

    def fail(self, error: str, cause: str | None = None) -> None:
        """The trial failed: ``error`` says why, ``cause`` names it in short (the report's tally)."""
        self.success, self.error, self.cause = False, error, cause

    def stage(self, what: str) -> None:
        """Report progress (the demo's spinner)."""
        if callable(self.on_stage):
            self.on_stage(what)

    def world(self, spec: SceneSpec) -> IcubLineWorld:
        """A world of ``spec`` for this trial (filmed when the trial makes a video)."""
        world = IcubLineWorld.from_layout(spec, gui=self.gui)
        if self.video is not None:
            self.video.attach(world)
        if self.recording is not None:
            self.recording.attach(world)
        return world

    def say(self, *lines: str) -> None:
        """The video's caption from now on, the recording's next step (nothing without either)."""
        if self.video is not None:
            self.video.caption(*lines)
        if self.recording is not None:
            self.recording.caption(*lines)

    def show(self, world: LineWorld, *lines: str) -> None:
        """Show ``world`` as it is now under ``lines`` for a moment (a step's outcome)."""
        if self.video is not None:
            self.video.caption(*lines)
            self.video.hold(world)
        if self.recording is not None:
            self.recording.caption(*lines)

    def observe(self, title: str, pre, post, grounding, step=None, far: dict[str, bool] | None = None) -> None:
        """An observed operation for the report (``pre``, ``post``: the camera's (H, W, 3) images,
        ``grounding`` their :class:`~vslsp.grounding.Grounding`, ``step`` the executed step) and the
        recording: the images and the symbolic state (``far``: every object's, else the grounded one's)."""
        self.observations.append((title, pre, post, grounding, step))
        if self.recording is not None:
            self.recording.observation(title, pre, post)
            if far is None and grounding is not None:
                far = {grounding.name: grounding.far_post}
            if far is not None:
                self.recording.state(
                    f"(far {name})" if is_far else f"(not (far {name}))" for name, is_far in far.items()
                )

    def show_step(self, world: LineWorld, label: str, result: StepResult, fault: str | None = None) -> None:
        """A step's outcome in the video: expected and observed, and the ``fault`` it carried."""
        verdict = "ok" if result.ok else "effect MISSING"
        carried = f" (FAULT {fault}: {FAULT_WHAT[fault]})" if fault else ""
        self.show(world, f"{label}{carried}", f"expected {result.expected}, observed {result.observed}: {verdict}")
