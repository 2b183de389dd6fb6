"""The task interface: every experiment of the paper is a :class:`Task` behind one registry.

A task names itself (``name``), its system of the paper (:class:`System`) and section
(``paper_section``), the common options it accepts (``options``), and runs one seeded trial
with :meth:`Task.run_trial`, which returns the one trial-result type, :class:`TrialResult`.
The trial runner (:mod:`vslsp.tasks.runner`) runs many trials (seeded, parallel, in seed
order) and the report (:mod:`vslsp.tasks.report`) writes the same folder layout for all:
``report.json``, ``report.md`` and the task's figures of one trial (:meth:`Task.figures`).

Writing a task::

    from vslsp.tasks import System, Task, TrialResult, register

    @register
    class CountToThree(Task):
        name = "count-to-three"
        system = System.VSL
        paper_section = "an example"
        description = "succeeds when the seed's draw is below 3"

        def run_trial(self, seed: int, keep: bool = False) -> TrialResult:
            value = int(np.random.default_rng(seed).integers(0, 4))
            if value < 3:
                return TrialResult(self.name, seed, True)
            return TrialResult(self.name, seed, False, f"drew {value}", failure_cause="a high draw")
"""

from __future__ import annotations

import enum
import os
import time
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar

if TYPE_CHECKING:
    from vslsp.perturbations import Perturbation


class System(enum.StrEnum):
    """The three systems of the paper."""

    VSL = "VSL"
    VSL_3D = "VSL-3D"
    VSL_SP = "VSL-SP"


class Option(enum.StrEnum):
    """Options of ``vslsp experiment`` that only some tasks take."""

    FAULTS = "faults"  # inject execution faults (a cube nudged back, a step skipped)
    PLANNER = "planner"  # the unified-planning oneshot planner
    SKILLS = "skills"  # the skill-library folder
    METHOD = "method"  # VSL-3D's match-finding method
    PREDICATES = "predicates"  # a Python file of the user's predicates (vslsp.grounding)
    VIDEO = "video"  # the report folder: each trial filmed into its videos/trial-SEED.mp4
    TUTOR_SLIPS = "tutor_slips"  # P: per demonstrated operation the tutor also disturbs another object
    SLIP_DETECTION = "slip_detection"  # False: the paper's VSL, which takes every change for the operation
    VIEWS = "views"  # VSL-3D's depth cameras: 1 (the paper's single view) or 2 (fused)
    RERUN = "rerun"  # the run's folder of recording parts: each trial logged into its trial-SEED.rrd
    PERTURB = "perturb"  # NAME=LEVEL items: how the reproduction's world differs (vslsp.perturbations)
    INTERVENTION = "intervention"  # tower-of-hanoi: whether the user makes the first move (by-seed, none, first-move)

    @property
    def flag(self) -> str:
        """The option as typed on the command line: ``--tutor-slips``."""
        return "--" + self.value.replace("_", "-")


class TrialStatus(enum.StrEnum):
    """How a trial ended (what ``success`` says, and for a failure, where it came from), as
    unified-planning's ``PlanGenerationResultStatus`` says how a planner ended."""

    SOLVED = "solved"  # the goal reached, judged on the simulator's ground truth
    FAILED = "failed"  # the trial ran to its end without reaching the goal (or learning the demonstration)
    RAISED = "raised"  # the trial raised an exception, recorded as its error
    LOST = "lost"  # the process that ran it ended during the trial (a crash, out of memory, a signal, Ray)


@dataclass
class TrialResult:
    """One trial of any task.

    ``success`` is judged on the simulator's ground truth; ``status`` says how the trial ended
    (:class:`TrialStatus`: ``SOLVED`` exactly when ``success``; left out, ``SOLVED`` or ``FAILED``
    by ``success``; a status that contradicts ``success`` is a ``ValueError``, as
    unified-planning checks a result's status against its plan); ``error`` says why a trial failed and
    ``failure_cause`` names the cause in short (what the report tallies, :attr:`cause`);
    ``operations`` holds one JSON record per operation (what moved, how it was found, how it
    ended); ``details`` holds the task's other JSON fields; ``artefacts`` holds what the report
    draws (images, demonstrations), kept only when the trial ran with ``keep``.
    """

    experiment: str
    seed: int
    success: bool
    error: str | None = None
    time_s: float = 0.0
    operations: list[dict] | None = None
    details: dict = field(default_factory=dict)
    artefacts: Any = field(default=None, repr=False, compare=False)
    cpu_s: float = 0.0
    stages_s: dict[str, float] | None = None  # wall seconds per stage (vslsp.stages), adding up to time_s
    video: str | None = None  # the trial's MP4, relative to the report folder (``--video``)
    failure_cause: str | None = None  # e.g. "no plan", "demonstration", the exception's type
    status: TrialStatus | None = None  # None: SOLVED or FAILED by ``success``

    def __post_init__(self) -> None:
        if self.status is None:
            self.status = TrialStatus.SOLVED if self.success else TrialStatus.FAILED
        if self.success != (self.status is TrialStatus.SOLVED):
            raise ValueError(f"a trial of status {self.status.value} cannot have success={self.success}")

    def to_dict(self) -> dict:
        """The trial's JSON record (``results`` of ``report.json``)."""
        data: dict = {
            "experiment": self.experiment,
            "seed": self.seed,
            "success": self.success,
            "status": str(self.status),
            "error": self.error,
            "time_s": round(self.time_s, 3),
            "cpu_s": round(self.cpu_s, 3),
        }
        if self.operations is not None:
            data["operations"] = self.operations
        data = {**data, **self.details}
        if self.stages_s is not None:
            data["stages_s"] = self.stages_s
        if self.video is not None:
            data["video"] = self.video
        return data

    @property
    def cause(self) -> str:
        """A short failure cause for the report's tally ("ok" for a success): ``failure_cause``;
        a task that names none has its ``error`` as the cause, or "goal not reached" without one."""
        if self.success:
            return "ok"
        return (self.failure_cause or self.error or "goal not reached")[:60]

    def without_artefacts(self) -> TrialResult:
        """The same result with nothing kept for the report (what crosses processes)."""
        return replace(self, artefacts=None)


class Task:
    """Base class of the registered experiments (see the module docstring for an example).

    Subclasses set the class attributes and implement :meth:`run_trial`; they may override
    :meth:`check` (options, before any work), :meth:`summary` (extra summary fields),
    :meth:`figures` (the report's pictures of one trial) and :meth:`shown_seed`.
    A task instance holds its options only, so that it can be sent to worker processes.
    """

    name: ClassVar[str]
    system: ClassVar[System]
    paper_section: ClassVar[str]
    description: ClassVar[str] = ""
    options: ClassVar[frozenset[Option]] = frozenset()
    keep_first: ClassVar[bool] = False  # the first trial keeps its artefacts (costly to re-run)

    def __init__(self, **options: Any) -> None:
        self.settings: dict[str, Any] = {k: v for k, v in options.items() if v is not None}

    def option(self, name: Option, default: Any = None) -> Any:
        """The value of a task option (``default`` when not given)."""
        return self.settings.get(name.value, default)

    def check(self) -> None:
        """Validate the options before any trial runs (raise :class:`InputError`)."""

    def perturbation(self) -> Perturbation:
        """The perturbation of ``--perturb`` (neutral when not given)."""
        from vslsp.perturbations import Perturbation  # numpy and OpenCV: only for a trial

        return Perturbation.parse(tuple(self.option(Option.PERTURB, ())))

    def run_trial(self, seed: int, keep: bool = False) -> TrialResult:
        """Run the trial of ``seed``; ``keep`` keeps the artefacts that :meth:`figures` draws."""
        raise NotImplementedError

    def summary(self, results: list[TrialResult]) -> dict:
        """Task-specific summary fields, added to the common ones of ``report.json``."""
        return {}

    def figures(self, folder: Path, shown: TrialResult) -> dict[str, Any]:
        """Write the report's pictures of ``shown`` (a trial run with ``keep``) into ``folder``;
        returns their paths relative to it (and any other JSON to show with them)."""
        return {}

    def shown_seed(self, results: list[TrialResult]) -> int:
        """The trial the report illustrates: the first failed one, else the first."""
        return next((r.seed for r in results if not r.success), results[0].seed)

    def markdown(self, data: Mapping[str, Any]) -> list[str]:
        """Task-specific lines of ``report.md`` after the summary table."""
        return []

    def pose_errors(self, result: TrialResult) -> list[tuple[float, float]]:
        """The final pose error of each operation of ``result`` that has one: (mm, deg)."""
        return []

    def paper_figures(self, data: Mapping[str, Any]) -> list[tuple[str, str, str]]:
        """Rows (measure, ours, the paper's) comparing this run with the figures the paper gives."""
        return []

    def describe(self) -> dict:
        """The entry of ``vslsp experiment --list --json``."""
        return {
            "name": self.name,
            "system": self.system.value,
            "paper_section": self.paper_section,
            "description": self.description,
            "options": sorted(o.value for o in self.options),
        }


def cpu_seconds() -> float:
    """CPU seconds used so far by this process and its finished children (the planner runs as
    one): unlike wall-clock time, hardly changed by other programs loading the machine."""
    times = os.times()
    return times.user + times.system + times.children_user + times.children_system


def video_path(seed: int) -> str:
    """Where the video of trial ``seed`` goes, relative to the report folder."""
    return f"videos/trial-{seed}.mp4"


def rerun_log(task: Task, seed: int) -> Any:
    """The rerun recording of trial ``seed`` (a :class:`~vslsp.sim.rerun_log.RerunLog`) when the
    task runs with ``--rerun``, else None; its part goes into the run's folder of parts."""
    parts = task.option(Option.RERUN)
    if not parts:
        return None
    from vslsp.sim.rerun_log import RerunLog, part_path, recording_id

    return RerunLog(part_path(parts, seed), seed, recording_id(parts))


def timed(task: Task, seed: int, keep: bool) -> TrialResult:
    """Run one trial and stamp its wall time and CPU time."""
    from vslsp import stages

    stages.reset()
    start, cpu = time.perf_counter(), cpu_seconds()
    result = task.run_trial(seed, keep)
    result.time_s = time.perf_counter() - start
    result.cpu_s = cpu_seconds() - cpu
    result.stages_s = stages.split(result.time_s)
    return result
