"""VSL-3D's stacking experiment (paper, "VSL-3D", "Stacking Objects") as a registered task.

Objects lie at random places with two boxes as dynamic landmarks; the tutor stacks each object
on its box; objects and boxes are moved to new random places and turns, and the Franka Panda
reproduces the stacks from the point clouds (:mod:`vslsp.vsl3d.stacking`): each box found in the
new cloud, each object grasped where its matched cloud says and put on its box as demonstrated.
"""

from __future__ import annotations

from typing import Any

from vslsp.tasks.registry import register
from vslsp.tasks.table_cleaning import Vsl3dExperiment


@register
class Stacking(Vsl3dExperiment):
    """Two objects stacked on two landmark boxes that move, reproduced by the robot."""

    name = "stacking"
    paper_section = "VSL-3D: Stacking Objects"
    description = (
        "The tutor stacks a duck and a teddy on two boxes (dynamic landmarks); objects and boxes are "
        "moved to new random places and turns and the Franka Panda reproduces the stacks from the "
        "RGB-D point clouds (success: each object within 1.5 cm and 15 deg of its demonstrated pose "
        "on its box, up to the box's symmetry)."
    )
    summary_line = "Stacks, errors relative to the box"

    def reproduce(self, seed: int, video: Any = None) -> tuple[list[dict], dict]:
        from vslsp.vsl3d.stacking import run_stacking

        outcome, pictures = run_stacking(seed, self.method, video=video)
        return [op.to_dict() for op in outcome], pictures
