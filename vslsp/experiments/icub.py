"""The paper's three iCub experiments of VSL-SP as registered tasks (paper, VSL-SP "Results").

- ``simple-vsl-task``: three objects, one demonstrated sequence, reproduced by VSL's own
  planner (match finding with adaptive frames, no PDDL) in a reshuffled scene;
- ``keep-all-near``: three demonstrations teach the rule "no block is far", which then solves
  scenes with other numbers and colours of objects;
- ``pull-in-order``: the ordered set <orange, green, yellow>, reproduced with VSL from a single
  demonstration and with VSL-SP through ``sometime-before`` constraints.

Each experiment's trial is its :meth:`IcubExperiment.play` (the scripts are in
:mod:`vslsp.experiments.icub_scripts`, imported only when a trial runs). The report shows, for one
trial, every observed pre/post pair with its grounding drawn (and the raw images beside, to
feed to ``vslsp ground``), the learned ``domain.pddl``, the first ``problem.pddl`` and plan,
and a figure of the executed hand trajectories.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from vslsp.errors import InputError, TaskFailed
from vslsp.experiments.icub_report import (
    fault_lines,
    learned_lines,
    matches_table_3,
    slip_lines,
    trial_rows,
    write_artefacts,
)
from vslsp.grounding.contained import shared_predicates
from vslsp.sim.video import SceneVideo, check_encoder
from vslsp.tasks.base import Option, System, Task, TrialResult, rerun_log, video_path
from vslsp.worlds.icub import check_layout

if TYPE_CHECKING:
    from vslsp.experiments.icub_faults import Faults
    from vslsp.experiments.icub_run import IcubRun
    from vslsp.skills.library import SkillLibrary

DEFAULT_PLANNER = "fast-downward"


class IcubExperiment(Task):
    """An iCub experiment: options ``faults``, ``planner`` and ``skills`` (the library folder)."""

    system = System.VSL_SP
    options = frozenset(
        {
            Option.FAULTS,
            Option.PLANNER,
            Option.SKILLS,
            Option.PREDICATES,
            Option.VIDEO,
            Option.TUTOR_SLIPS,
            Option.SLIP_DETECTION,
            Option.RERUN,
        }
    )
    keep_first = True  # a trial takes tens of seconds: the first one's artefacts travel back instead of a re-run
    # The sides of the cubes (True: beyond the line) of each scene the experiment lays out with
    # fixed sides (vslsp.worlds.icub.line_layout): checked before the first trial.
    layouts: tuple[tuple[bool, ...], ...] = ()

    def check(self) -> None:
        """The skill library loads and has push and pull (a missing or corrupt one, or a missing
        skill, is reported before any work); the planner exists; every declared layout can be laid
        out (:func:`vslsp.worlds.icub.check_layout`)."""
        from vslsp.skills.library import SKILL_NAMES, SkillLibrary
        from vslsp.symbolic import check_planner

        for far in self.layouts:
            check_layout(tuple(bool(side) for side in far))

        check_planner(self.option(Option.PLANNER, DEFAULT_PLANNER))
        SkillLibrary.load(self.library_path).require(SKILL_NAMES, self.library_path)
        self.predicates()  # a predicates file that does not load is reported before any work
        if self.option(Option.VIDEO):
            check_encoder()
        if self.option(Option.RERUN):
            from vslsp.sim.rerun_log import check_rerun

            check_rerun()

    @property
    def library_path(self) -> Path:
        from vslsp.skills.library import default_library_path

        skills = self.option(Option.SKILLS)
        return Path(skills) if skills else default_library_path()

    def predicates(self) -> tuple:
        """The user's predicates (``--predicates FILE.py``), decided in one child process per file and
        process for the whole run (:func:`vslsp.grounding.contained.shared_predicates`); () without one."""

        path = self.option(Option.PREDICATES)
        return shared_predicates(path) if path else ()

    def play(
        self, trial: IcubRun, rng: np.random.Generator, library: SkillLibrary, faults: Faults, planner: str
    ) -> None:
        """The experiment's trial: demonstrate, learn, reproduce and judge, into ``trial``
        (task failures raise :class:`~vslsp.errors.TaskFailed`)."""
        raise NotImplementedError

    def run(
        self,
        seed: int,
        library: SkillLibrary,
        *,
        gui: bool = False,
        on_stage=None,
        video: str | Path | None = None,
        recording: Any = None,
    ) -> IcubRun:
        """Run the trial of ``seed`` with the task's options (faults, planner, predicates); user
        errors propagate, task failures are recorded. ``video``: an MP4 file to film the trial
        into (:class:`~vslsp.sim.video.SceneVideo`); ``recording``: the trial's rerun recording
        (:class:`~vslsp.sim.rerun_log.RerunLog`), closed with the trial."""

        from vslsp.experiments.icub_faults import Fault, Faults, fault_log
        from vslsp.experiments.icub_run import IcubRun
        from vslsp.loop.pipeline import describe_learned

        faults = bool(self.option(Option.FAULTS, False))
        trial = IcubRun(seed, gui=gui, on_stage=on_stage, predicates=self.predicates())
        if video is not None:
            trial.video = SceneVideo(video)
        trial.recording = recording
        if self.slips_given:
            from vslsp.experiments.icub_slips import Watcher

            trial.watcher = Watcher(
                seed, float(self.option(Option.TUTOR_SLIPS, 0.0)), bool(self.option(Option.SLIP_DETECTION, True))
            )
        rng = np.random.default_rng(seed)
        kinds = tuple(fault.value for fault in Fault)  # drawn by value: the same seed, the same fault
        fault_plan = {int(rng.integers(0, 2)): str(rng.choice(kinds))} if faults else {}
        if faults:
            trial.details["faults"] = {str(k): v for k, v in fault_plan.items()}
        trial.faults = Faults(fault_plan)
        try:
            self.play(trial, rng, library, trial.faults, self.option(Option.PLANNER, DEFAULT_PLANNER))
        except TaskFailed as failure:
            trial.fail(str(failure), failure.cause)
        except InputError as failure:  # what the robot learned does not fit the scene: a failed trial
            trial.fail(f"{type(failure).__name__}: {failure}", type(failure).__name__)
        finally:
            if trial.video is not None:
                trial.video.close()
            if trial.recording is not None:
                trial.recording.close()
        if faults:  # where each fault fired (the plan may be shorter than the drawn step), explained
            planned = {id(step) for run in trial.executions for step in run.steps}
            trial.details["fault_log"] = fault_log(trial.steps, planned, trial.error or "the trial ended")
            trial.details["faults"] = {str(entry["step"] - 1): entry["kind"] for entry in trial.details["fault_log"]}
        if trial.watcher is not None:
            trial.details.update(trial.watcher.details())
        if trial.domain is not None or trial.task is not None:
            trial.details["learned"] = describe_learned(trial.domain, trial.task)
        plans = [plan for run in trial.executions for plan in run.plans]
        if plans:
            trial.details["plan_length"] = len(plans[0].steps)
            trial.details["planning_s"] = round(sum(plan.time_s for plan in plans), 3)
        trial.failed_steps = sum(not s.ok for s in trial.steps)
        if trial.failed_steps:
            trial.details["step_errors"] = [f"{s.action} {s.obj}: {s.error}" for s in trial.steps if not s.ok]
        if trial.predicates:
            trial.details["predicates"] = [p.name for p in trial.predicates]
            if trial.domain is not None:
                trial.details["action_models"] = [line for a in trial.domain.actions for line in _model_lines(a)]
            if trial.task is not None:
                trial.details["rules"] = [str(rule) for rule in trial.task.rules]
        return trial

    @property
    def slips_given(self) -> bool:
        """Whether the run was asked for the tutor's slips or their detection (without either, a
        trial is exactly what it was before them)."""
        return self.option(Option.TUTOR_SLIPS) is not None or self.option(Option.SLIP_DETECTION) is not None

    def run_trial(self, seed: int, keep: bool = False, on_stage=None, gui: bool = False) -> TrialResult:
        from vslsp.skills.library import SkillLibrary

        folder = self.option(Option.VIDEO)
        trial = self.run(
            seed,
            SkillLibrary.load(self.library_path),
            gui=gui,
            on_stage=on_stage,
            video=Path(folder) / video_path(seed) if folder else None,
            recording=rerun_log(self, seed),
        )
        planned = {id(step) for run in trial.executions for step in run.steps}
        operations = [
            {"operation": i, **step.to_dict(), "system": "VSL-SP" if id(step) in planned else "VSL"}
            for i, step in enumerate(trial.steps, start=1)
        ]
        return TrialResult(
            self.name,
            seed,
            trial.success,
            trial.error,
            operations=operations,
            details={"replans": trial.replans, "failed_steps": trial.failed_steps, **trial.details},
            artefacts=trial if keep else None,
            video=video_path(seed) if folder else None,
            failure_cause=trial.cause,
        )

    def summary(self, results: list[TrialResult]) -> dict:
        data = {
            "faults": bool(self.option(Option.FAULTS, False)),
            "replans": sum(r.details.get("replans", 0) for r in results),
            "failed_steps": sum(r.details.get("failed_steps", 0) for r in results),
        }
        if data["faults"]:
            data["faults_fired"] = sum(len(r.details.get("fault_log", [])) for r in results)
            data["trials_with_a_fired_fault"] = sum(bool(r.details.get("fault_log")) for r in results)
        if self.slips_given:
            from vslsp.experiments.icub_slips import summary

            data["tutor_slips"] = float(self.option(Option.TUTOR_SLIPS, 0.0))
            data["slip_detection"] = bool(self.option(Option.SLIP_DETECTION, True))
            data.update(summary(results))
        return data

    def shown_seed(self, results: list[TrialResult]) -> int:
        return results[0].seed  # kept by the run (keep_first)

    def markdown(self, data: Mapping[str, Any]) -> list[str]:
        fired = (
            f", {data['faults_fired']} faults injected and fired ({data['trials_with_a_fired_fault']} of "
            f"{data['trials']} trials)"
            if data["faults"]
            else ""
        )
        lines = [f"{data['replans']} replans, {data['failed_steps']} failed steps{fired}.", ""]
        lines += trial_rows(data["results"]) + fault_lines(data["results"]) + slip_lines(data)
        lines += learned_lines(data["results"])
        return lines

    def paper_figures(self, data: Mapping[str, Any]) -> list[tuple[str, str, str]]:
        learned = [r["learned"] for r in data["results"] if r.get("learned", {}).get("action_models")]
        if not learned:
            return []
        same = sum(matches_table_3(model) for model in learned)
        return [
            (
                "action models (push, pull) as Table 3",
                f"{same}/{len(learned)} trials learned them",
                "push: pre (not (far ?b)), eff (far ?b); pull: pre (far ?b), eff (not (far ?b))",
            )
        ]

    def figures(self, folder: Path, shown: TrialResult) -> dict[str, Any]:
        trial = shown.artefacts
        files = write_artefacts(folder, trial, shown.details.get("fault_log", []))
        if trial.task is not None:
            files["rules"] = [str(rule) for rule in trial.task.rules]
        return files


class SimpleVslTask(IcubExperiment):
    name = "simple-vsl-task"
    paper_section = "VSL-SP Results: simple VSL task"
    description = (
        "Three cubes, one demonstrated sequence, reproduced by VSL's own planner (match finding with "
        "adaptive frames, no PDDL) in a reshuffled scene."
    )

    def play(
        self, trial: IcubRun, rng: np.random.Generator, library: SkillLibrary, faults: Faults, planner: str
    ) -> None:
        from vslsp.experiments.icub_scripts import simple_vsl_task

        simple_vsl_task(trial, rng, library, faults, planner)


class KeepAllNear(IcubExperiment):
    name = "keep-all-near"
    paper_section = "VSL-SP Results: keep all objects near"
    description = (
        "Three demonstrations teach the rule 'no block is far', which then solves scenes with other "
        "numbers and colours of objects (PDDL + Fast Downward)."
    )

    def play(
        self, trial: IcubRun, rng: np.random.Generator, library: SkillLibrary, faults: Faults, planner: str
    ) -> None:
        from vslsp.experiments.icub_scripts import keep_all_near

        keep_all_near(trial, rng, library, faults, planner)


class PullInOrder(IcubExperiment):
    name = "pull-in-order"
    paper_section = "VSL-SP Results: pull in order"
    description = (
        "The ordered set <orange, green, yellow>, reproduced with VSL from a single demonstration and with "
        "VSL-SP through sometime-before constraints."
    )

    def play(
        self, trial: IcubRun, rng: np.random.Generator, library: SkillLibrary, faults: Faults, planner: str
    ) -> None:
        from vslsp.experiments.icub_scripts import pull_in_order

        pull_in_order(trial, rng, library, faults, planner)


def _model_lines(action) -> list[str]:
    """An action model in two readable lines: its preconditions and its effects (PDDL)."""
    effects = " ".join(e.to_pddl() for e in action.effects)
    return [f"{action.name}: pre {action.precondition.to_pddl()}", f"{action.name}: eff {effects}"]
