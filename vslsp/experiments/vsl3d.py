"""VSL-3D's experiments executed by the robot (paper, "VSL-3D"): their base and the two registered
experiments, table cleaning and stacking.

The experiments run in :mod:`vslsp.experiments.table_cleaning` and
:mod:`vslsp.experiments.stacking`, imported only inside a trial (the point-cloud method loads
torch: listing the experiments stays cheap). Every operation's record carries
``"executed_by": "robot"``, the grasp outcome per attempt, the match fitness and the final
position/turn error against the simulator's truth (tolerances 1.5 cm and 15 deg). ``--views 2``
adds the far RGB-D sensor: every capture is the two sensors' clouds fused by their known poses.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from vslsp.errors import InputError
from vslsp.outputs import output_subfolder
from vslsp.sim.video import SceneVideo, check_encoder, tabletop_scene_camera
from vslsp.tasks.base import Option, System, Task, TrialResult, rerun_log, video_path
from vslsp.tasks.drawing import label
from vslsp.vision.image import write_image


def operation_summary(results: list[TrialResult]) -> dict:
    """Summary fields over the operations of VSL-3D trials (shared by table cleaning and stacking)."""
    operations = [op for r in results for op in (r.operations or [])]
    errors_mm = sorted(op["final_error_mm"] for op in operations if op["success"])
    errors_deg = sorted(op["final_error_deg"] for op in operations if op["success"])
    return {
        "operations": len(operations),
        "operations_succeeded": sum(op["success"] for op in operations),
        "retried_grasps": sum(len(op.get("grasp_outcome") or []) > 1 for op in operations),
        "median_error_mm": float(errors_mm[len(errors_mm) // 2]) if errors_mm else None,
        "median_error_deg": float(errors_deg[len(errors_deg) // 2]) if errors_deg else None,
    }


def operation_failures(operations: list[dict]) -> list[str]:
    """One line per failed operation: its diagnosis, or how far from the goal it ended."""
    return [
        f"operation {op['index']} ({op['moved']}): "
        + (
            op.get("error")
            or f"ended {op['final_error_mm']} mm / {op['final_error_deg']} deg from the "
            f"demonstrated pose (held {op['picked']})"
        )
        for op in operations
        if not op["success"]
    ]


def vsl3d_figures(folder: Path, pictures: dict) -> dict[str, Any]:
    """Write a VSL-3D trial's pictures (see :func:`vslsp.experiments.table_cleaning.run_table_cleaning`)."""
    from vslsp.vsl3d.pictures import write_clouds

    output_subfolder(folder, "images")
    files: dict[str, Any] = {}

    def write(key: str, image: Any, caption: str) -> None:
        files[key] = f"images/{key}.png"
        write_image(folder / files[key], label(image, caption))

    for index, image in enumerate(pictures["demonstration"], start=1):
        write(
            f"demonstration_{index}",
            image,
            f"demonstration {index}: pre-action (found object, red) | post-action (green)",
        )
    for index, image in enumerate(pictures["matched"], start=1):
        write(f"reproduction_{index}", image, f"reproduction {index}: matched observation (red), grasp (yellow)")
    write("cloud", pictures["cloud"], "the reproduction's point cloud, one colour per segment")
    write("final", pictures["final"], "demonstrated final scene | reproduced final scene")
    return {**files, **write_clouds(folder, pictures.get("clouds") or {})}


class Vsl3dExperiment(Task):
    """A VSL-3D experiment executed by the robot: the ``--method`` option, the trial record from the
    operations' records, the summary over the operations and the pictures. Subclasses give
    :meth:`reproduce` and the report's sentence (:attr:`summary_line`)."""

    system = System.VSL_3D
    options = frozenset(
        {Option.METHOD, Option.VIDEO, Option.VIEWS, Option.TUTOR_SLIPS, Option.SLIP_DETECTION, Option.RERUN}
    )
    summary_line = "Operations"
    # A trial draws its pictures whether kept or not: the first one's travel back instead of the
    # report re-running that whole trial (about a quarter of a 2-trial run's CPU).
    keep_first = True

    def check(self) -> None:
        from vslsp.vsl3d.alignment import METHODS

        if self.method not in METHODS:
            raise InputError(f"unknown --method {self.method!r}; choose one of {', '.join(METHODS)}")
        views = self.option(Option.VIEWS, 1)
        if isinstance(views, bool) or views not in (1, 2):
            raise InputError(f"--views takes 1 (the paper's single view) or 2 (two fused depth cameras), got {views!r}")
        slips = self.option(Option.TUTOR_SLIPS)
        if slips is not None and not 0.0 <= float(slips) <= 1.0:
            raise InputError(f"--tutor-slips is a probability from 0 to 1, not {slips}")
        if self.option(Option.VIDEO):
            check_encoder()
        if self.option(Option.RERUN):
            from vslsp.sim.rerun_log import check_rerun

            check_rerun()

    @property
    def method(self) -> str:
        return str(self.option(Option.METHOD, "prerejective_ransac"))

    @property
    def views(self) -> int:
        """The RGB-D sensors whose clouds are fused: 1 (the paper's single view) or 2."""
        return int(self.option(Option.VIEWS, 1))

    def recorded_views(self) -> dict[str, int]:
        """``{"views": n}`` when ``--views`` was given (the report of a run without it stays as
        it was; the studio re-runs a trial with it)."""
        return {"views": self.views} if Option.VIEWS in self.settings else {}

    def reproduce(self, seed: int, video: Any = None, recording: Any = None) -> tuple[list[dict], dict]:
        """Demonstrate and reproduce the trial of ``seed`` (filmed by ``video``, a
        :class:`~vslsp.sim.video.SceneVideo`, and logged by ``recording``, a
        :class:`~vslsp.sim.rerun_log.RerunLog`, when given): the operations' records and the pictures."""
        raise NotImplementedError

    @property
    def slips(self) -> dict[str, Any]:
        """The tutor's slips as the experiments take them: ``tutor_slips`` (None: not given) and
        ``slip_detection`` (on unless turned off: off is the paper's getObject, the baseline)."""
        slips = self.option(Option.TUTOR_SLIPS)
        return {
            "tutor_slips": None if slips is None else float(slips),
            "slip_detection": bool(self.option(Option.SLIP_DETECTION, True)),
        }

    def run_trial(self, seed: int, keep: bool = False) -> TrialResult:
        folder = self.option(Option.VIDEO)
        video = SceneVideo(Path(folder) / video_path(seed), camera=tabletop_scene_camera()) if folder else None
        recording = rerun_log(self, seed)
        try:
            operations, pictures = self.reproduce(seed, video, recording)
        finally:
            if video is not None:
                video.close()
            if recording is not None:
                recording.close()
        failed = [op for op in operations if not op["success"]]
        return TrialResult(
            self.name,
            seed,
            not failed,
            "; ".join(operation_failures(operations)) or None,
            operations=operations,
            details={"method": self.method, **self.recorded_views()},
            artefacts=pictures if keep else None,
            video=video_path(seed) if video is not None else None,
            failure_cause=f"operation {failed[0]['index']} ({failed[0]['moved']})" if failed else None,
        )

    def summary(self, results: list[TrialResult]) -> dict:
        given = any(self.option(o) is not None for o in (Option.TUTOR_SLIPS, Option.SLIP_DETECTION))
        if not given:
            return {"method": self.method, **self.recorded_views(), **operation_summary(results)}
        operations = [op for r in results for op in (r.operations or [])]
        found = [op for op in operations if op.get("slip") and (op.get("demonstration") or {}).get("disturbed")]
        return {
            "method": self.method,
            **self.recorded_views(),
            **operation_summary(results),
            **self.slips,
            "operations_slipped": sum(bool(op.get("slip")) for op in operations),
            "slips_found": len(found),
        }

    def markdown(self, data: Mapping[str, Any]) -> list[str]:
        return [
            f"{self.summary_line} (executed by the robot): {data['operations_succeeded']}/{data['operations']} "
            f"succeeded, {data['retried_grasps']} after a retried grasp; median final error "
            f"{data['median_error_mm']} mm, {data['median_error_deg']} deg (method {data['method']}"
            + (f", {data['views']} fused depth cameras" if data.get("views", 1) > 1 else "")
            + ").",
            "",
            *(
                [
                    f"Tutor slips (P = {data['tutor_slips']}): {data['operations_slipped']} operations slipped, "
                    f"{data['slips_found']} found disturbed by the slip detection "
                    f"({'on' if data['slip_detection'] else 'off: getObject as in the paper'}).",
                    "",
                ]
                if "operations_slipped" in data
                else []
            ),
        ]

    def figures(self, folder: Path, shown: TrialResult) -> dict[str, Any]:
        return vsl3d_figures(folder, shown.artefacts)

    def pose_errors(self, result: TrialResult) -> list[tuple[float, float]]:
        """Each operation's final error against the demonstrated pose (simulator truth)."""
        return [
            (op["final_error_mm"], op["final_error_deg"])
            for op in result.operations or []
            if op.get("final_error_mm") is not None and op.get("final_error_deg") is not None
        ]


class TableCleaning(Vsl3dExperiment):
    """Two objects into the box, the third in front of it, reproduced by the robot from point clouds."""

    name = "table-cleaning"
    paper_section = "VSL-3D: Table Cleaning"
    description = (
        "The tutor puts two objects into the box and the third in front of it; the objects are "
        "reshuffled and the Franka Panda reproduces the task from the RGB-D point clouds "
        "(success: each object within 1.5 cm and 15 deg of its demonstrated pose)."
    )

    def reproduce(self, seed: int, video: Any = None, recording: Any = None) -> tuple[list[dict], dict]:
        from vslsp.experiments.table_cleaning import run_table_cleaning

        outcome, pictures = run_table_cleaning(
            seed, self.method, video, views=self.views, recording=recording, **self.slips
        )
        return [op.to_dict() for op in outcome.operations], pictures


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

    def reproduce(self, seed: int, video: Any = None, recording: Any = None) -> tuple[list[dict], dict]:
        from vslsp.experiments.stacking import run_stacking

        outcome, pictures = run_stacking(
            seed, self.method, video=video, views=self.views, recording=recording, **self.slips
        )
        return [op.to_dict() for op in outcome], pictures
