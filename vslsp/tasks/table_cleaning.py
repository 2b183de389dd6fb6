"""VSL-3D's table-cleaning experiment (paper, "VSL-3D", "Table Cleaning") as a registered task.

The tutor puts two objects into the box and one in front of it while the RGB-D sensor watches;
the objects are reshuffled and VSL-3D reproduces the task from the point clouds
(:mod:`vslsp.vsl3d.table_cleaning`). The report shows, for one trial, the demonstration's
pre-/post-action RGB views with the found object's frame and the final scene.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from vslsp.errors import InputError
from vslsp.tasks.base import Option, System, Task, TrialResult
from vslsp.tasks.registry import register

METHODS = ("prerejective_ransac", "sac_ia", "icp")  # as vslsp.vsl3d.alignment.METHODS (heavy to import)


@register
class TableCleaning(Task):
    """Two objects into the box, the third in front of it, reproduced from point clouds."""

    name = "table-cleaning"
    system = System.VSL_3D
    paper_section = "VSL-3D: Table Cleaning"
    description = ("The tutor puts two objects into the box and the third in front of it; the objects are "
                   "reshuffled and VSL-3D reproduces the task from the RGB-D point clouds.")
    options = frozenset({Option.METHOD})

    def check(self) -> None:
        if self.method not in METHODS:
            raise InputError(f"unknown --method {self.method!r}; choose one of {', '.join(METHODS)}")

    @property
    def method(self) -> str:
        return str(self.option(Option.METHOD, "prerejective_ransac"))

    def run_trial(self, seed: int, keep: bool = False) -> TrialResult:
        from vslsp.vsl3d.table_cleaning import run_table_cleaning

        outcome, images, final = run_table_cleaning(seed, self.method)
        operations = [op.to_dict() for op in outcome.operations]
        failures = [f"operation {op.index} ({op.moved}): "
                    + (op.error or f"ended {op.final_error_mm} mm / {op.final_error_deg} deg from the demonstrated "
                                   f"pose (picked {op.picked})")
                    for op in outcome.operations if not op.success]
        return TrialResult(self.name, seed, outcome.success, "; ".join(failures) or None, operations=operations,
                           details={"method": self.method}, artefacts=(images, final) if keep else None)

    def summary(self, results: list[TrialResult]) -> dict:
        operations = [op for r in results for op in (r.operations or [])]
        errors_mm = sorted(op["final_error_mm"] for op in operations if op["success"])
        errors_deg = sorted(op["final_error_deg"] for op in operations if op["success"])
        return {"method": self.method, "operations": len(operations),
                "operations_succeeded": sum(op["success"] for op in operations),
                "median_error_mm": float(errors_mm[len(errors_mm) // 2]) if errors_mm else None,
                "median_error_deg": float(errors_deg[len(errors_deg) // 2]) if errors_deg else None}

    def markdown(self, data: Mapping[str, Any]) -> list[str]:
        return [f"Operations: {data['operations_succeeded']}/{data['operations']} succeeded; median final error "
                f"{data['median_error_mm']} mm, {data['median_error_deg']} deg (method {data['method']}).", ""]

    def figures(self, folder: Path, shown: TrialResult) -> dict[str, Any]:
        from vslsp.tasks.drawing import label
        from vslsp.vision.image import write_image

        images, final = shown.artefacts
        (folder / "images").mkdir(parents=True, exist_ok=True)
        files: dict[str, Any] = {}
        for index, image in enumerate(images, start=1):
            files[f"demonstration_{index}"] = f"images/demonstration_{index}.png"
            write_image(folder / files[f"demonstration_{index}"],
                        label(image, f"operation {index}: pre-action (found object, red) | post-action (green)"))
        files["reproduction_final"] = "images/reproduction_final.png"
        write_image(folder / files["reproduction_final"], label(final, "reproduction: final scene"))
        return files
