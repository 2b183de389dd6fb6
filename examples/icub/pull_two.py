"""An iCub task of one's own, through the public hooks of vslsp.experiments.icub_scripts
(docs/tasks.md, "A task on the iCub"): the robot learns push and pull by trying them, watches the
tutor pull two cubes to its side of the line, learns the goal (and the order), and then plans and
executes it with its skills in a new scene, observing and replanning. Run it with

    vslsp experiment --tasks examples/icub/pull_two.py pull-two --trials 3
"""

from __future__ import annotations

from vslsp.experiments.icub import IcubExperiment
from vslsp.experiments.icub_scripts import execute, explore, narration, record, watch
from vslsp.experiments.seeds import reproduction_seed
from vslsp.symbolic import learn_task
from vslsp.tasks import register
from vslsp.worlds.icub import line_layout

COLOURS = ("green", "orange")
BOTH_FAR = (True, True)


@register
class PullTwo(IcubExperiment):
    name = "pull-two"
    paper_section = "an example: a task of one's own on the iCub"
    description = "Two cubes pulled to the robot's side, learned from one demonstration, planned and executed."
    layouts = (BOTH_FAR,)  # checked before the first trial (an impossible layout: exit 2)

    def play(self, trial, rng, library, faults, planner) -> None:
        explore(trial, rng, library)  # the robot's own push and pull: the action models (trial.domain)
        with trial.world(line_layout(trial.seed, COLOURS, BOTH_FAR)) as world:
            steps = watch(world, trial, [(c, "pull") for c in COLOURS], "demonstration")
        trial.task = learn_task([steps], ordered=True)  # the goal and the demonstrated order
        with trial.world(line_layout(reproduction_seed(trial.seed), COLOURS, BOTH_FAR)) as world:
            before, after = narration(trial, world)
            run = execute(trial, world, library, faults, planner, before, after)
            final = {c.colour: world.is_far(c.name) for c in world.spec.cubes}  # the simulator's truth
        record(trial, run)
        trial.success = run.success and not any(final.values())
        # the report's VSL-SP column reads vsl_sp_success (and vsl_sp_order): docs/tasks.md
        trial.details.update({"vsl_sp_success": trial.success, "final_far": final})
        if not trial.success and trial.error is None:
            trial.fail(f"cubes still far: {[c for c, f in final.items() if f]}", "cubes still far")
