"""The house-roof experiment (paper, "Simulation", Figure 4, roof placement): VSL's adaptive frames.

Each trial records the tutor's demonstration in a world built from the trial's seed (three
identical house bodies, three roofs: two put on their bodies, the third upside down below its
body), builds a new world from the seed (bodies and roofs at random places and angles) and
reproduces the demonstration twice, with a fixed small pre-place frame and with the adaptive
one. A trial succeeds when the adaptive reproduction reaches the demonstrated goal on the
ground truth; the fixed frame's outcome is reported beside it. The report's pictures show the
demonstration, the match finding with both frames, the reproductions side by side and the
pick-and-place trajectories of "Methodology".
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import cv2
import numpy as np

from vslsp.errors import InputError
from vslsp.experiments.house_roof_trial import (
    PIXEL_SIZE,
    ObservationFeatures,
    demonstrate,
    pick_frame,
    place_frames,
    reproduce,
)
from vslsp.experiments.seeds import reproduction_seed
from vslsp.experiments.slip_pictures import mark_moves, moves_caption
from vslsp.outcomes import Diagnosis
from vslsp.outputs import atomic_file, output_subfolder
from vslsp.tasks.base import Option, System, Task, TrialResult
from vslsp.tasks.drawing import PICK, PLACE, label, point, small, square, with_legend
from vslsp.vision.image import write_image
from vslsp.vsl.slips.detect import UnseenOperation
from vslsp.worlds.house_roof.board import HouseWorld
from vslsp.worlds.house_roof.camera import BoardCamera

FRAMES = ("fixed", "adaptive")  # the values of vslsp.vision.matching.FrameMode, as the report orders them
PIXEL_MM = 1.0  # mm per px of the board (vslsp.experiments.house_roof_trial.PIXEL_SIZE, heavy to import)


class HouseRoof(Task):
    """VSL without a robot: the paper's 2-D house-and-roof simulation."""

    name = "house-roof"
    system = System.VSL
    options = frozenset({Option.TUTOR_SLIPS, Option.SLIP_DETECTION, Option.PERTURB})
    paper_section = "Simulation (Figure 4: roof placement)"
    description = (
        "The tutor puts two roofs on their house bodies and the third upside down below its body; each "
        "trial reproduces it in a new random world with a fixed small pre-place frame and with the "
        "adaptive frame (success: the adaptive one), judged on the ground truth."
    )

    def run_trial(self, seed: int, keep: bool = False) -> TrialResult:
        """Demonstrate in the world of ``seed``, reproduce with both frame policies in the world of
        :func:`~vslsp.experiments.seeds.reproduction_seed`; ``keep`` holds on to the images for the report."""

        slips = self.option(Option.TUTOR_SLIPS)
        drawn = self.perturbation().draw(seed)
        try:
            demo = demonstrate(seed, slips, bool(self.option(Option.SLIP_DETECTION, True)))
        except InputError as unseen:  # the recorder could not see the tutor's operation
            return TrialResult(
                self.name,
                seed,
                False,
                f"demonstration: {unseen}",
                operations=_slip_records(unseen.slips if isinstance(unseen, UnseenOperation) else (), slips),
                details={"reproduction_ms": {}},
                failure_cause="demonstration",
            )
        features = ObservationFeatures(demo)
        world = HouseWorld.random(reproduction_seed(seed))
        results, milliseconds, reproductions = {}, {}, {}
        for frame in FRAMES:
            clock = time.perf_counter()
            camera = None if drawn.none else BoardCamera(drawn, world)  # each frame sees the same images
            reproduction = reproduce(demo, world, frame, features, camera)
            milliseconds[frame] = round(1000.0 * (time.perf_counter() - clock), 1)
            results[frame] = reproduction.to_dict()
            reproductions[frame] = reproduction
        success = bool(results["adaptive"]["success"])
        error, cause = (None, None) if success else _failure(results["adaptive"])
        return TrialResult(
            self.name,
            seed,
            success,
            error,
            # with --tutor-slips: per demonstrated operation what moved, which was operated, the slip
            operations=_slip_records(demo.slips, slips),
            details={
                "reproduction_ms": milliseconds,
                **results,
                **({} if camera is None else {"perturbation": camera.to_dict()}),
            },
            artefacts=(demo, reproductions) if keep else None,
            failure_cause=cause,
        )

    def summary(self, results: list[TrialResult]) -> dict:
        """Per-frame success rates, per-operation rates and diagnoses, ms per reproduction."""
        total = len(results)
        data: dict[str, Any] = {}
        for frame in FRAMES:
            done = [r.details for r in results if frame in r.details]
            operations = [op for d in done for op in d[frame]["operations"]]
            successes = sum(d[frame]["success"] for d in done)
            times = [d["reproduction_ms"][frame] for d in done]
            data[f"{frame}_frame"] = {
                "successes": successes,
                "success_rate": successes / total if total else 0.0,
                "operations": len(operations),
                "operations_ok": sum(op["diagnosis"] == Diagnosis.OK for op in operations),
                "diagnoses": {
                    d: sum(op["diagnosis"] == d for op in operations)
                    for d in sorted({op["diagnosis"] for op in operations})
                },
                "ms_per_reproduction": round(sum(times) / len(times), 1) if times else None,
            }
        if self.option(Option.TUTOR_SLIPS) is not None:  # the studio re-runs a trial with these
            data["tutor_slips"] = self.option(Option.TUTOR_SLIPS)
            data["slip_detection"] = bool(self.option(Option.SLIP_DETECTION, True))
        return data

    def shown_seed(self, results: list[TrialResult]) -> int:
        """The first trial in which the fixed frame failed (it shows why frames adapt), else the first."""
        failed_fixed = [r for r in results if "fixed" in r.details and not r.details["fixed"]["success"]]
        return (failed_fixed or results)[0].seed

    def markdown(self, data: Mapping[str, Any]) -> list[str]:
        lines = [
            "| frame | successes | success rate | operations ok | diagnoses | ms per reproduction |",
            "|---|---|---|---|---|---|",
        ]
        for frame in FRAMES:
            f = data[f"{frame}_frame"]
            diagnoses = ", ".join(f"{k}: {v}" for k, v in f["diagnoses"].items())
            lines.append(
                f"| {frame} | {f['successes']}/{data['trials']} | {100 * f['success_rate']:.1f} % | "
                f"{f['operations_ok']}/{f['operations']} | {diagnoses} | {f['ms_per_reproduction']} |"
            )
        return lines + [""]

    def figures(self, folder: Path, shown: TrialResult) -> dict[str, Any]:
        return _figures(folder, *shown.artefacts)

    def pose_errors(self, result: TrialResult) -> list[tuple[float, float]]:
        """The adaptive frame's roofs against the slot they landed in (1 px is 1 mm of the board)."""
        operations = result.details.get("adaptive", {}).get("operations", [])
        return [
            (op["position_error_px"] * PIXEL_MM, op["angle_error_deg"])
            for op in operations
            if op.get("position_error_px") is not None
        ]

    def paper_figures(self, data: Mapping[str, Any]) -> list[tuple[str, str, str]]:
        fixed, adaptive = data["fixed_frame"], data["adaptive_frame"]
        return [
            (
                "fixed frame: reproductions reaching the goal",
                f"{fixed['successes']}/{data['trials']}",
                "can fail: the 3rd roof goes on a house that already has one (O1 = O2, Figure 4c)",
            ),
            (
                "adaptive frame: reproductions reaching the goal",
                f"{adaptive['successes']}/{data['trials']}",
                "correct: the growing frame sees the roof already placed (Figure 4c)",
            ),
        ]


def _slip_records(records: tuple[dict, ...], slips: float | None) -> list[dict] | None:
    """With ``--tutor-slips``: per demonstrated operation what moved, which one was operated,
    which were disturbed, and the tutor's ``slip`` (ground truth) when one happened."""
    return None if slips is None else [{"operation": k, **r} for k, r in enumerate(records, start=1)]


def _failure(adaptive: dict) -> tuple[str, str]:
    """Which operations of the adaptive reproduction failed, and why; the cause: the first of them."""
    failed = [
        (i, op["diagnosis"]) for i, op in enumerate(adaptive["operations"], start=1) if op["diagnosis"] != Diagnosis.OK
    ]
    if not failed:
        return "goal not reached", "goal not reached"
    return "; ".join(f"operation {i}: {diagnosis}" for i, diagnosis in failed), f"operation {failed[0][0]}"


def _figures(folder: Path, demonstration, reproductions: dict) -> dict:
    output_subfolder(folder, "images")
    files = {
        "demonstration": "images/demonstration.png",
        "final_worlds": "images/final_worlds.png",
        "trajectory": "images/trajectory.png",
    }
    write_image(folder / files["demonstration"], _demonstration_picture(demonstration))
    for frame in FRAMES:
        files[f"matches_{frame}"] = f"images/matches_{frame}.png"
        write_image(folder / files[f"matches_{frame}"], _matches_picture(demonstration, reproductions[frame], frame))
    write_image(folder / files["final_worlds"], _final_worlds_picture(demonstration, reproductions))
    _trajectory_figure(folder / files["trajectory"], reproductions["adaptive"])
    return files


def _demonstration_picture(demo) -> np.ndarray:
    """One row per operation: pre-pick (pick frame), pre-place (first place frame), post."""

    rows = []
    for k, op in enumerate(demo.demonstration.operations, start=1):
        pre, pre_place, post = op.pre_observation.copy(), demo.pre_place[k - 1].copy(), op.post_observation.copy()
        square(pre, (op.pose_pre.x, op.pose_pre.y), pick_frame(op.object_size), PICK)
        square(pre_place, (op.pose_post.x, op.pose_post.y), place_frames("fixed", op.object_size)[0], PLACE)
        cv2.arrowedLine(
            post,
            point((op.pose_pre.x, op.pose_pre.y)),
            point((op.pose_post.x, op.pose_post.y)),
            PICK,
            2,
            cv2.LINE_AA,
            tipLength=0.05,
        )
        title = f"op {k}: post (turn {np.degrees(demo.turns[k - 1]):.0f} deg)"
        if demo.slips:  # with --tutor-slips: the objects that moved, as the slip detection found them
            post = demo.actual_posts[k - 1].copy() if demo.actual_posts else post
            mark_moves(post, demo.moves[k - 1] if demo.moves else None, demo.slips[k - 1])
            title = f"op {k}: post; {moves_caption(demo.slips[k - 1])}"
        panels = [
            label(small(pre), f"op {k}: pre-pick"),
            label(small(pre_place), f"op {k}: pre-place"),
            label(small(post), title),
        ]
        rows.append(np.hstack(panels))
    return with_legend(
        np.vstack(rows),
        [
            ("square", PICK, "pick frame: the object before, 1.5 object sizes"),
            ("square", PLACE, "place frame: where it goes, 2 object sizes"),
            ("arrow", PICK, "the tutor's move"),
        ],
    )


def _matches_picture(demo, reproduction, frame: str) -> np.ndarray:
    """For each operation, the world the place was searched in: the pick frame (magenta) and
    the place frame that decided (azure) mapped into it by their transforms."""

    panels = []
    for k, (op, result) in enumerate(zip(demo.demonstration.operations, reproduction.operations), start=1):
        image = (
            reproduction.pre_place_worlds[k - 1]
            if k - 1 < len(reproduction.pre_place_worlds)
            else reproduction.world_before.render()
        ).copy()
        if result.pick is not None:
            corners = result.pick.frame_corners(pick_frame(op.object_size), (op.pose_pre.x, op.pose_pre.y))
            cv2.polylines(image, [np.round(corners).astype(np.int32)], True, PICK, 2, cv2.LINE_AA)
        text = f"op {k}: {result.diagnosis}"
        if result.place is not None:
            corners = result.place.frame_corners(result.place.frame, (op.pose_post.x, op.pose_post.y))
            cv2.polylines(image, [np.round(corners).astype(np.int32)], True, PLACE, 3, cv2.LINE_AA)
            cv2.drawMarker(image, point((result.place.x, result.place.y)), PLACE, cv2.MARKER_CROSS, 20, 2)
            text += (
                f", frame {result.place.frame} px, score {result.place.score:.2f}"
                f"{' (ambiguous)' if result.place.ambiguous else ''}"
            )
        panels.append(label(small(image), text))
    marks = [
        ("square", PICK, "pick frame, mapped into this world by its match"),
        ("square", PLACE, "the place frame that decided, mapped likewise"),
        ("cross", PLACE, "where the object goes"),
    ]
    return with_legend(label(np.hstack(panels), f"{frame} frame", (8, 58)), marks)


def _final_worlds_picture(demo, reproductions: dict) -> np.ndarray:
    panels = [label(small(demo.world_after.render()), "demonstration: goal")]
    for frame in FRAMES:
        reproduction = reproductions[frame]
        verdict = "goal reached" if reproduction.success else "WRONG"
        panels.append(label(small(reproduction.world_after.render()), f"{frame} frame: {verdict}"))
    return np.hstack(panels)


def _trajectory_figure(path: Path, reproduction) -> None:
    """The hand's paths over the reproduction world (x, y), its height and rotation in time."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    world = reproduction.world_before.render()
    height, width = world.shape[:2]
    figure = plt.figure(figsize=(13, 5.5))
    top = figure.add_subplot(1, 2, 1)
    top.imshow(world, extent=(0, width * PIXEL_SIZE, height * PIXEL_SIZE, 0))
    z_axis, theta_axis = figure.add_subplot(2, 2, 2), figure.add_subplot(2, 2, 4)
    clock = 0.0
    for k, result in enumerate(reproduction.operations, start=1):
        if result.trajectory is None:
            continue
        t, xyz, theta = result.trajectory.t + clock, result.trajectory.xyz, result.trajectory.theta
        (line,) = top.plot(xyz[:, 0], xyz[:, 1], lw=2, label=f"op {k}: {result.diagnosis}")
        top.plot(*xyz[result.trajectory.segments[1], :2], "o", color=line.get_color())
        top.plot(*xyz[result.trajectory.segments[2], :2], "s", color=line.get_color())
        z_axis.plot(t, xyz[:, 2], color=line.get_color())
        theta_axis.plot(t, np.degrees(theta), color=line.get_color())
        clock = t[-1]
    top.set(
        xlim=(0, width * PIXEL_SIZE),
        ylim=((height + 120) * PIXEL_SIZE, 0),
        xlabel="x (m)",
        ylabel="y (m)",
        title="hand paths rest → pick (o) → place (□) → rest",
    )
    top.legend(loc="lower left", fontsize=8)
    z_axis.set(ylabel="height z (m)", title="height profile h[1 − |atanh(h0(s − 0.5))/atanh(h0/2)|^κ]")
    theta_axis.set(xlabel="t (s)", ylabel="hand rotation θ (deg)", title="trapezoidal rotation profile")
    figure.tight_layout()
    with atomic_file(path) as stream:
        figure.savefig(stream, dpi=90, format="png")
    plt.close(figure)
