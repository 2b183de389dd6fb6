"""VSL-3D's stacking experiment (paper, "VSL-3D", "Stacking Objects") as a registered task.

Objects lie at random places with two boxes as dynamic landmarks; the tutor stacks each object
on its box; objects and boxes are moved to new random places and turns, and the Franka Panda
reproduces the stacks from the point clouds (:mod:`vslsp.vsl3d.stacking`): each box found in the
new cloud, each object grasped where its matched cloud says and put on its box as demonstrated.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from vslsp.errors import InputError
from vslsp.tasks.base import Option, System, Task, TrialResult
from vslsp.tasks.registry import register
from vslsp.tasks.table_cleaning import METHODS, operation_failures, operation_summary, vsl3d_figures


@register
class Stacking(Task):
    """Two objects stacked on two landmark boxes that move, reproduced by the robot."""

    name = "stacking"
    system = System.VSL_3D
    paper_section = "VSL-3D: Stacking Objects"
    description = (
        "The tutor stacks a duck and a teddy on two boxes (dynamic landmarks); objects and boxes are "
        "moved to new random places and turns and the Franka Panda reproduces the stacks from the "
        "RGB-D point clouds (success: each object within 1.5 cm and 15 deg of its demonstrated pose "
        "on its box, up to the box's symmetry)."
    )
    options = frozenset({Option.METHOD})

    def check(self) -> None:
        if self.method not in METHODS:
            raise InputError(f"unknown --method {self.method!r}; choose one of {', '.join(METHODS)}")

    @property
    def method(self) -> str:
        return str(self.option(Option.METHOD, "prerejective_ransac"))

    def run_trial(self, seed: int, keep: bool = False) -> TrialResult:
        from vslsp.vsl3d.stacking import run_stacking

        outcome, pictures = run_stacking(seed, self.method)
        operations = [op.to_dict() for op in outcome]
        success = all(op["success"] for op in operations)
        return TrialResult(
            self.name,
            seed,
            success,
            "; ".join(operation_failures(operations)) or None,
            operations=operations,
            details={"method": self.method},
            artefacts=pictures if keep else None,
        )

    def summary(self, results: list[TrialResult]) -> dict:
        return {"method": self.method, **operation_summary(results)}

    def markdown(self, data: Mapping[str, Any]) -> list[str]:
        return [
            f"Stacks (executed by the robot): {data['operations_succeeded']}/{data['operations']} succeeded, "
            f"{data['retried_grasps']} after a retried grasp; median final error {data['median_error_mm']} mm, "
            f"{data['median_error_deg']} deg relative to the box (method {data['method']}).",
            "",
        ]

    def figures(self, folder: Path, shown: TrialResult) -> dict[str, Any]:
        return vsl3d_figures(folder, shown.artefacts)
