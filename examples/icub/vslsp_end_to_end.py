"""VSL-SP end to end in a few lines, through the library API (docs/api.md): what ``vslsp demo``
does, without its report. The iCub loads its shipped push and pull skills, tries each once and
learns their action models from what it sees (VSL grounds ``far`` before and after), watches the
tutor pull the orange, green and yellow cubes to its side of the line in that order, learns the
goal and the order (PDDL 3.0 ``sometime-before``), and in a new scene plans with Fast Downward
and executes the plan with its skills, checking every step's effect and replanning on a failure.
Run it with

    python examples/icub/vslsp_end_to_end.py [SEED]
"""

from __future__ import annotations

import sys

from vslsp import api

COLOURS = ("orange", "green", "yellow")


def main(seed: int) -> api.Execution:
    library = api.shipped_skills()
    explorations = []
    for k, action in enumerate(("push", "pull")):  # the robot tries each skill on one cube
        layout = api.line_layout(1000 + seed + k, ("red",), (action == "pull",))
        with api.IcubLineWorld.from_layout(layout) as world:
            explorations.append(api.explore_skill(world, library, action))
    domain = api.learn_models(explorations)
    print(domain.to_pddl())
    with api.IcubLineWorld.from_layout(api.line_layout(seed, COLOURS, (True,) * 3)) as world:
        steps = api.watch_tutor(world, [(colour, "pull") for colour in COLOURS])
    task = api.learn_task([steps], ordered=True)
    with api.IcubLineWorld.from_layout(api.line_layout(seed + 1, COLOURS, (True,) * 3)) as world:
        run = api.execute_task(world, library, domain, task)
        still_far = [cube.colour for cube in world.spec.cubes if world.is_far(cube.name)]  # the truth
    print(f"plan: {', '.join(run.plans[0].lines())}; executed: {', '.join(run.executed)}; {run.replans} replans")
    print("succeeded" if run.success and not still_far else f"failed: {run.error or still_far}")
    return run


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 0)
