"""vslsp as a library: the objects a researcher composes, in the order of the paper's data flow
(docs/api.md is the reference; each name below is there with its signature and an example).

- a world: :class:`World` (the protocol) and the paper's four, :class:`IcubLineWorld`,
  :class:`PandaTable`, :class:`RgbdTable`, :class:`HouseBoard`; an iCub scene is a
  :class:`SceneSpec` (:func:`line_layout`), the tutor's push or pull :func:`tutor_operation`;
- VSL (Algorithm 1): a demonstration from a folder of pictures (:func:`read_recording`,
  :func:`learn_demonstration`, :func:`load_learned`), or recorded observation by observation
  (:class:`Recorder` with :class:`TableModel` or :class:`ImagePlane`), reproduced in a new scene
  (:func:`reproduce`, :class:`Session`);
- grounding: :func:`ground` (the moved object, ``far`` before and after, the action, and the
  user's own :func:`predicate` s), :func:`ground_scene`, :func:`load_predicates`;
- the skills: :class:`SkillLibrary` (:func:`shipped_skills`), taught by :func:`teach_skill`,
  run by :func:`execute_skill`;
- VSL-SP: the robot tries its skills (:func:`explore_skill`) and learns their action models
  (:func:`learn_models`, :func:`learn_domain`), watches the tutor (:func:`watch_tutor`), learns
  the task (:func:`learn_task`), states it in a scene (:func:`make_problem`), plans
  (:func:`plan`), validates (:func:`validate`), and executes with monitoring
  (:func:`execute_task`: every step's effect checked, replanning on a failure);
- a task of one's own: :class:`Task`, :func:`register`, :func:`get_task`, :func:`run_trials`.

Every name is imported on first use, so that ``from vslsp.api import ground`` loads perception
only, and ``import vslsp`` nothing of it. Errors meant for the user are :class:`VslspError` s.

Example (VSL-SP in a few lines; examples/icub/vslsp_end_to_end.py runs it)::

    from vslsp import api

    library = api.shipped_skills()
    with api.IcubLineWorld.from_layout(api.line_layout(1, ("green",), (False,))) as world:
        push = api.explore_skill(world, library, "push")
    ...
"""

from __future__ import annotations

import importlib
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import numpy as np

    from vslsp.errors import VslspError
    from vslsp.grounding import (
        Grounding,
        Predicate,
        SceneGrounding,
        load_predicates,
        predicate,
        true_atoms,
        unary_literals,
        with_builtins,
    )
    from vslsp.grounding.operation import ground, ground_scene
    from vslsp.loop.monitor import StepResult, execute_step
    from vslsp.loop.perception import PerceivedState, perceive
    from vslsp.loop.pipeline import Execution, Exploration, execute_task, explore_skill, learn_models
    from vslsp.sim import Observation
    from vslsp.sim.scene import CubeSpec, LandmarkSpec, SceneSpec
    from vslsp.skills.execute import execute_skill
    from vslsp.skills.library import Skill, SkillLibrary
    from vslsp.symbolic import (
        Domain,
        LearnedTask,
        PlanResult,
        Problem,
        Step,
        Validation,
        learn_domain,
        learn_task,
        make_problem,
        read_domain,
        read_problem,
        validate,
    )
    from vslsp.tasks import System, Task, TrialResult, TrialStatus, get_task, register, run_trials
    from vslsp.vision.parameters import FrameSearch, ObjectFinding
    from vslsp.vsl.calibration import Calibration
    from vslsp.vsl.demonstration import ImagePlane
    from vslsp.vsl.learned import Learned, Session, load_learned, save_learned
    from vslsp.vsl.pick_place import PickPlaceDemonstration, TableModel
    from vslsp.vsl.recorder import Heights, Recorder
    from vslsp.vsl.recordings import Recording, read_recording
    from vslsp.vsl3d.parameters import CloudMatching, Grasping
    from vslsp.worlds import World
    from vslsp.worlds.house_roof import HouseBoard
    from vslsp.worlds.icub import IcubLineWorld, line_layout, tutor_operation
    from vslsp.worlds.panda_table import PandaTable
    from vslsp.worlds.rgbd_table import RgbdTable

#: Each re-exported name -> (its module, its name there).
_HOME: dict[str, tuple[str, str]] = {
    "VslspError": ("vslsp.errors", "VslspError"),
    # worlds
    "World": ("vslsp.worlds", "World"),
    "IcubLineWorld": ("vslsp.worlds.icub", "IcubLineWorld"),
    "PandaTable": ("vslsp.worlds.panda_table", "PandaTable"),
    "RgbdTable": ("vslsp.worlds.rgbd_table", "RgbdTable"),
    "HouseBoard": ("vslsp.worlds.house_roof", "HouseBoard"),
    "SceneSpec": ("vslsp.sim.scene", "SceneSpec"),
    "CubeSpec": ("vslsp.sim.scene", "CubeSpec"),
    "LandmarkSpec": ("vslsp.sim.scene", "LandmarkSpec"),
    "Observation": ("vslsp.sim", "Observation"),
    "line_layout": ("vslsp.worlds.icub", "line_layout"),
    "tutor_operation": ("vslsp.worlds.icub", "tutor_operation"),
    # VSL: recording and reproduction
    "Recorder": ("vslsp.vsl.recorder", "Recorder"),
    "Heights": ("vslsp.vsl.recorder", "Heights"),
    "TableModel": ("vslsp.vsl.pick_place", "TableModel"),
    "ImagePlane": ("vslsp.vsl.demonstration", "ImagePlane"),
    "PickPlaceDemonstration": ("vslsp.vsl.pick_place", "PickPlaceDemonstration"),
    "Recording": ("vslsp.vsl.recordings", "Recording"),
    "read_recording": ("vslsp.vsl.recordings", "read_recording"),
    "Calibration": ("vslsp.vsl.calibration", "Calibration"),
    "Learned": ("vslsp.vsl.learned", "Learned"),
    "save_learned": ("vslsp.vsl.learned", "save_learned"),
    "load_learned": ("vslsp.vsl.learned", "load_learned"),
    "Session": ("vslsp.vsl.learned", "Session"),
    # the algorithms' tuned rules (parameter objects)
    "FrameSearch": ("vslsp.vision.parameters", "FrameSearch"),
    "ObjectFinding": ("vslsp.vision.parameters", "ObjectFinding"),
    "CloudMatching": ("vslsp.vsl3d.parameters", "CloudMatching"),
    "Grasping": ("vslsp.vsl3d.parameters", "Grasping"),
    # grounding
    "ground": ("vslsp.grounding.operation", "ground"),
    "ground_scene": ("vslsp.grounding.operation", "ground_scene"),
    "Grounding": ("vslsp.grounding.operation", "Grounding"),
    "SceneGrounding": ("vslsp.grounding.operation", "SceneGrounding"),
    "predicate": ("vslsp.grounding.predicates", "predicate"),
    "Predicate": ("vslsp.grounding.predicates", "Predicate"),
    "load_predicates": ("vslsp.grounding.loader", "load_predicates"),
    "with_builtins": ("vslsp.grounding.loader", "with_builtins"),
    "true_atoms": ("vslsp.grounding.predicates", "true_atoms"),
    "unary_literals": ("vslsp.grounding.predicates", "unary_literals"),
    # skills
    "Skill": ("vslsp.skills.library", "Skill"),
    "SkillLibrary": ("vslsp.skills.library", "SkillLibrary"),
    "execute_skill": ("vslsp.skills.execute", "execute_skill"),
    # VSL-SP: perception, exploration, learning, planning, execution with monitoring
    "perceive": ("vslsp.loop.perception", "perceive"),
    "PerceivedState": ("vslsp.loop.perception", "PerceivedState"),
    "explore_skill": ("vslsp.loop.pipeline", "explore_skill"),
    "Exploration": ("vslsp.loop.pipeline", "Exploration"),
    "learn_models": ("vslsp.loop.pipeline", "learn_models"),
    "Step": ("vslsp.symbolic.learning.learn", "Step"),
    "learn_domain": ("vslsp.symbolic.learning.learn", "learn_domain"),
    "learn_task": ("vslsp.symbolic.learning.learn", "learn_task"),
    "LearnedTask": ("vslsp.symbolic.learning.learn", "LearnedTask"),
    "make_problem": ("vslsp.symbolic.learning.learn", "make_problem"),
    "Domain": ("vslsp.symbolic.model.domain", "Domain"),
    "Problem": ("vslsp.symbolic.model.domain", "Problem"),
    "read_domain": ("vslsp.symbolic.io.pddl", "read_domain"),
    "read_problem": ("vslsp.symbolic.io.pddl", "read_problem"),
    "PlanResult": ("vslsp.symbolic.engines.planner", "PlanResult"),
    "validate": ("vslsp.symbolic.validation.validate", "validate"),
    "Validation": ("vslsp.symbolic.validation.validate", "Validation"),
    "execute_step": ("vslsp.loop.monitor", "execute_step"),
    "StepResult": ("vslsp.loop.monitor", "StepResult"),
    "execute_task": ("vslsp.loop.pipeline", "execute_task"),
    "Execution": ("vslsp.loop.pipeline", "Execution"),
    # a task of one's own
    "Task": ("vslsp.tasks.base", "Task"),
    "System": ("vslsp.tasks.base", "System"),
    "TrialResult": ("vslsp.tasks.base", "TrialResult"),
    "TrialStatus": ("vslsp.tasks.base", "TrialStatus"),
    "register": ("vslsp.tasks.registry", "register"),
    "get_task": ("vslsp.tasks.registry", "get_task"),
    "run_trials": ("vslsp.tasks.runner", "run_trials"),
}


def __getattr__(name: str) -> Any:
    if name in _HOME:
        module, attribute = _HOME[name]
        value = getattr(importlib.import_module(module), attribute)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'vslsp.api' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(__all__)


# --- what the API composes itself ---------------------------------------------------------------


def learn_demonstration(folder: str | Path, out: str | Path | None = None) -> Learned:
    """Algorithm 1 part I on a folder of pictures (docs/recordings.md: ``01-pre.png``,
    ``01-mid.png``, ``01-post.png``, ...; optional ``calibration.json``, ``names.json``,
    ``heights.json``): each operation's moved object, its pick and place, its features. With
    ``out`` (an existing folder) the demonstration is also written there, as
    ``vslsp vsl learn FOLDER --out OUT`` writes it (:func:`load_learned` reads it back).
    Raises :class:`~vslsp.errors.InputError` naming the file of a bad recording,
    :class:`~vslsp.errors.GroundingFailed` naming an operation whose object is not found.

    Example::

        learned = api.learn_demonstration("recording/")
        print(len(learned), learned.names)        # 3 ('A', 'B', 'C')
    """
    from vslsp.vsl.learned import Learned, save_learned
    from vslsp.vsl.recordings import learn, read_recording

    recording = read_recording(folder)
    demonstration = learn(recording)
    if out is not None:
        save_learned(demonstration, recording, out)
    return Learned(demonstration, recording.calibration, recording.names, recording.size)


def reproduce(learned: Learned, scene: str | Path | np.ndarray, operation: int = 0) -> dict:
    """Algorithm 1 part II for one operation: where to pick and place operation ``operation``
    (0-based) of ``learned`` in ``scene``, a picture (a file, or an (H, W, 3) uint8 RGB array)
    of the new world. A dict as ``vslsp vsl reproduce --json`` prints it: ``pick`` and
    ``place`` (``pixel``; with a calibration ``table_m`` (x, y), ``hand_angle_rad``, ``z_m``),
    ``turn_rad``, ``grasp_width_m`` (calibrated), the matches. Raises
    :class:`~vslsp.errors.TaskFailed` when the object or its place is not found.

    Example::

        answer = api.reproduce(learned, "scene.png", 0)
        robot.pick_and_place(answer["pick"]["table_m"], answer["place"]["table_m"])
    """
    from vslsp.vision.image import read_image
    from vslsp.vsl.learned import next_operation

    image = read_image(scene) if isinstance(scene, str | Path) else scene
    return next_operation(learned, operation, image)


def shipped_skills() -> SkillLibrary:
    """The push and pull skills that ship with vslsp (the repository's ``skills/``, taught by
    ``vslsp teach``), loaded. Example: ``library = api.shipped_skills(); library["pull"]``."""
    from vslsp.skills.library import SkillLibrary, default_library_path

    return SkillLibrary.load(default_library_path())


def teach_skill(skill: str, seeds: Sequence[int], n_basis: int = 50) -> Skill:
    """Teach ``skill`` (``push`` or ``pull``) by imitation: the tutor's kinesthetic demonstration
    in a fresh iCub scene of each seed, the reach fitted as a DMP with ``n_basis`` basis
    functions and the move as the mean displacement (paper, "Learning skills by imitation").
    Raises InputError when no demonstration moved the cube across the line.

    Example::

        library = api.SkillLibrary({"push": api.teach_skill("push", range(5)), "pull": shipped["pull"]})
    """
    from vslsp.skills.teach import learn_skill, record_demonstration

    return learn_skill(skill, [record_demonstration(skill, seed) for seed in seeds], n_basis=n_basis)


def watch_tutor(
    world: IcubLineWorld, operations: Sequence[tuple[str, str]], predicates: Sequence[Predicate] | None = None
) -> list[Step]:
    """The tutor's demonstration in ``world`` as the robot sees it: the tutor performs each
    ``(colour, action)`` of ``operations`` (``action``: push or pull) and the robot grounds every
    pre/post pair of its head camera into a :class:`Step` (``far`` and, with ``predicates``,
    the user's unary predicates before and after): what :func:`learn_task` learns from.

    Example::

        with api.IcubLineWorld.from_layout(api.line_layout(3, ("orange", "green"), (True, True))) as world:
            steps = api.watch_tutor(world, [("orange", "pull"), ("green", "pull")])
        task = api.learn_task([steps], ordered=True)
    """
    from vslsp.grounding.operation import ground
    from vslsp.loop.perception import perceive
    from vslsp.loop.pipeline import to_step
    from vslsp.worlds.icub import tutor_operation

    steps = []
    state = perceive(world)
    for colour, action in operations:
        tutor_operation(world, colour, action)
        after = perceive(world)
        steps.append(to_step(ground(state.image, after.image), state, after, predicates))
        state = after
    return steps


def plan(domain: Domain, problem: Problem, planner: str = "fast-downward", timeout: float | None = 300.0) -> PlanResult:
    """A plan for ``problem`` in ``domain`` by ``planner`` (unified-planning's oneshot planners;
    Fast Downward by default), PDDL 3.0 trajectory constraints included; ``timeout`` in
    wall-clock seconds (None: none). Raises :class:`~vslsp.symbolic.engines.outcomes.NoPlan` (a
    TaskFailed with its status) when there is none or a limit was reached.

    Example::

        problem = api.make_problem(domain, task, {"green": {"far": True}})
        result = api.plan(domain, problem)
        print(result.lines())                     # ['(pull green)']
    """
    from vslsp.symbolic.engines.planner import solve

    return solve(domain, problem, planner, timeout=timeout)


__all__ = [
    "Calibration",
    "CloudMatching",
    "CubeSpec",
    "Domain",
    "Execution",
    "Exploration",
    "FrameSearch",
    "Grasping",
    "Grounding",
    "Heights",
    "HouseBoard",
    "IcubLineWorld",
    "ImagePlane",
    "LandmarkSpec",
    "Learned",
    "LearnedTask",
    "ObjectFinding",
    "Observation",
    "PandaTable",
    "PerceivedState",
    "PickPlaceDemonstration",
    "PlanResult",
    "Predicate",
    "Problem",
    "Recorder",
    "Recording",
    "RgbdTable",
    "SceneGrounding",
    "SceneSpec",
    "Session",
    "Skill",
    "SkillLibrary",
    "Step",
    "StepResult",
    "System",
    "TableModel",
    "Task",
    "TrialResult",
    "TrialStatus",
    "Validation",
    "VslspError",
    "World",
    "execute_skill",
    "execute_step",
    "execute_task",
    "explore_skill",
    "get_task",
    "ground",
    "ground_scene",
    "learn_demonstration",
    "learn_domain",
    "learn_models",
    "learn_task",
    "line_layout",
    "load_learned",
    "load_predicates",
    "make_problem",
    "perceive",
    "plan",
    "predicate",
    "read_domain",
    "read_problem",
    "read_recording",
    "register",
    "reproduce",
    "run_trials",
    "save_learned",
    "shipped_skills",
    "teach_skill",
    "true_atoms",
    "tutor_operation",
    "unary_literals",
    "validate",
    "watch_tutor",
    "with_builtins",
]
