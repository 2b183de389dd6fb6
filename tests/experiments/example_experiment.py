"""A new experiment on an existing world, in one module (docs/tasks.md shows this file)."""

from vslsp.experiments.tabletop import TabletopExperiment
from vslsp.tasks import register


@register
class TwoLettersInARow(TabletopExperiment):
    """On the Panda table: the tutor puts B, then A beside it, by the baseline; the robot
    reproduces both from a new scatter (relative positioning: A is judged against B)."""

    name = "two-letters-in-a-row"
    paper_section = "an example on the Panda table"
    description = "B put by the baseline, then A beside it; reproduced from a new scatter."

    def layout(self, rng, phase):
        from vslsp.worlds.panda_table import layouts

        letters = layouts.letters()[:2]  # A and B
        keep_out = [(0.635, y, 0.05) for y in (0.13, 0.06)]  # where the tutor puts them
        return layouts.baseline_arms() + list(zip(letters, layouts.scatter(rng, letters, keep_out)))

    def moves(self, rng):
        from vslsp.geometry.poses import compose
        from vslsp.worlds.panda_table import Placement

        yield "B", (lambda world: Placement(0.635, 0.06, 0.0)), "baseline-long"

        def beside_b(world):  # A on B's left, wherever B lies (the tutor sees the truth)
            x, y, _, yaw = world.truth("B")
            return Placement(*compose((x, y, yaw), (0.0, 0.07, 0.0)))

        yield "A", beside_b, "B"
