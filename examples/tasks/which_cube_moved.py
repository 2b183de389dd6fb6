"""A task of one's own through the library API (docs/tasks.md, docs/api.md): one class,
registered, run as seeded trials with the common runner (and by ``vslsp experiment --tasks
examples/tasks/which_cube_moved.py which-cube-moved --trials 5``).

Each trial lays out three cubes in the iCub line world from its seed; the tutor pulls one of the
far ones across the line; the robot tells from its head camera's pre- and post-action pictures
which cube moved and that it is no longer far (VSL's grounding of ``far``). Success is judged on
the simulator's ground truth, which perception never reads. Run it with

    python examples/tasks/which_cube_moved.py [TRIALS]
"""

from __future__ import annotations

import sys

import numpy as np

from vslsp import api

COLOURS = ("red", "green", "blue")


@api.register
class WhichCubeMoved(api.Task):
    name = "which-cube-moved"
    system = api.System.VSL_SP
    paper_section = "an example: a task of one's own, through vslsp.api"
    description = "The tutor pulls one far cube; the robot grounds which cube moved and that it is now near."

    def run_trial(self, seed: int, keep: bool = False) -> api.TrialResult:
        rng = np.random.default_rng(seed)  # everything from the seed
        far = (True, bool(rng.integers(2)), bool(rng.integers(2)))
        with api.IcubLineWorld.from_layout(api.line_layout(seed, COLOURS, far)) as world:
            pulled = str(rng.choice([c for c, f in zip(COLOURS, far) if f]))
            before = api.perceive(world)
            api.tutor_operation(world, pulled, "pull")
            after = api.perceive(world)
            seen = api.ground(before.image, after.image)
            truth_far = {cube.colour: world.is_far(cube.name) for cube in world.spec.cubes}
        success = seen.name == pulled and seen.action == "pull" and not truth_far[pulled]
        error = None if success else f"the robot saw {seen.action} {seen.name}; the tutor pulled {pulled}"
        return api.TrialResult(
            self.name,
            seed,
            success,
            error,
            operations=[{"operation": 1, "pulled": pulled, "seen": seen.name, "action": seen.action}],
            details={"pulled": pulled},
        )


def main(trials: int) -> list[api.TrialResult]:
    run = api.run_trials(api.get_task("which-cube-moved"), list(range(trials)))
    for result in run.results:
        print(f"seed {result.seed}: {'ok' if result.success else result.error}")
    print(f"{sum(r.success for r in run.results)}/{trials} trials succeeded")
    return run.results


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 3)
