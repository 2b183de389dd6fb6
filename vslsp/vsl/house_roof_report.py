"""The house-roof experiment's report folder: ``report.json`` (the summary and every trial),
``report.md``, and pictures of one trial (paper, Figure "3Houses": the demonstration, the
match finding with both frames, the reproductions side by side, and the pick-and-place
trajectories of "Methodology")."""

from __future__ import annotations

import json
from pathlib import Path

import cv2
import numpy as np

from vslsp.vision.image import write_image
from vslsp.vsl.house_roof import PIXEL_SIZE, Reproduction, frame_box, pick_frame, place_frames
from vslsp.vsl.tasks import FRAMES, HouseRoofTrial, run_trial, summary

_PICK, _PLACE, _TEXT = (255, 0, 255), (0, 170, 255), (255, 255, 255)  # RGB
_SCALE = 0.5  # pictures at half the camera's resolution


def write_report(folder: str | Path, trials: list[HouseRoofTrial], seed: int) -> dict:
    """Write the report folder for ``trials`` (seeds from ``seed``); the pictures show the first
    trial in which the fixed frame failed (else the first), re-run with its images. Returns the
    summary written to report.json."""
    folder = Path(folder)
    (folder / "images").mkdir(parents=True, exist_ok=True)
    data = summary(trials, seed)
    failed_fixed = [t for t in trials if t.results and not t.results["fixed"]["success"]]
    shown = run_trial((failed_fixed or trials)[0].seed, keep=True)
    files = _figures(folder, shown) if shown.demonstration is not None else {}
    data["shown_trial"] = {"seed": shown.seed, **files}
    data["results"] = [t.to_dict() for t in trials]
    data["report"] = str(folder)
    (folder / "report.json").write_text(json.dumps(data, indent=2) + "\n")
    (folder / "report.md").write_text(_markdown(data, trials))
    return data


def _figures(folder: Path, trial: HouseRoofTrial) -> dict:
    files = {"demonstration": "images/demonstration.png", "final_worlds": "images/final_worlds.png",
             "trajectory": "images/trajectory.png"}
    write_image(folder / files["demonstration"], _demonstration_picture(trial))
    for frame in FRAMES:
        files[f"matches_{frame}"] = f"images/matches_{frame}.png"
        write_image(folder / files[f"matches_{frame}"], _matches_picture(trial, frame))
    write_image(folder / files["final_worlds"], _final_worlds_picture(trial))
    _trajectory_figure(folder / files["trajectory"], trial.reproductions["adaptive"])
    return files


def _demonstration_picture(trial: HouseRoofTrial) -> np.ndarray:
    """One row per operation: pre-pick (pick frame), pre-place (first place frame), post."""
    demo = trial.demonstration
    rows = []
    for k, op in enumerate(demo.demonstration.operations, start=1):
        pre, pre_place, post = op.pre_observation.copy(), demo.pre_place[k - 1].copy(), op.post_observation.copy()
        _square(pre, (op.pose_pre.x, op.pose_pre.y), pick_frame(op.object_size), _PICK)
        _square(pre_place, (op.pose_post.x, op.pose_post.y), place_frames("fixed", op.object_size)[0], _PLACE)
        cv2.arrowedLine(post, _int((op.pose_pre.x, op.pose_pre.y)), _int((op.pose_post.x, op.pose_post.y)), _PICK, 2,
                        cv2.LINE_AA, tipLength=0.05)
        panels = [_label(_small(pre), f"op {k}: pre-pick"), _label(_small(pre_place), f"op {k}: pre-place"),
                  _label(_small(post), f"op {k}: post (turn {np.degrees(demo.turns[k - 1]):.0f} deg)")]
        rows.append(np.hstack(panels))
    return np.vstack(rows)


def _matches_picture(trial: HouseRoofTrial, frame: str) -> np.ndarray:
    """For each operation, the world the place was searched in: the pick frame (magenta) and
    the place frame that decided (orange) mapped into it by their transforms."""
    demo, reproduction = trial.demonstration, trial.reproductions[frame]
    panels = []
    for k, (op, result) in enumerate(zip(demo.demonstration.operations, reproduction.operations), start=1):
        image = (reproduction.pre_place_worlds[k - 1] if k - 1 < len(reproduction.pre_place_worlds)
                 else reproduction.world_before.render()).copy()
        if result.pick is not None:
            corners = frame_box(result.pick, pick_frame(op.object_size), (op.pose_pre.x, op.pose_pre.y))
            cv2.polylines(image, [np.round(corners).astype(np.int32)], True, _PICK, 2, cv2.LINE_AA)
        text = f"op {k}: {result.diagnosis}"
        if result.place is not None:
            corners = frame_box(result.place, result.place.frame, (op.pose_post.x, op.pose_post.y))
            cv2.polylines(image, [np.round(corners).astype(np.int32)], True, _PLACE, 3, cv2.LINE_AA)
            cv2.drawMarker(image, _int((result.place.x, result.place.y)), _PLACE, cv2.MARKER_CROSS, 20, 2)
            text += (f", frame {result.place.frame} px, score {result.place.score:.2f}"
                     f"{' (ambiguous)' if result.place.ambiguous else ''}")
        panels.append(_label(_small(image), text))
    return _label(np.hstack(panels), f"{frame} frame", (8, 58))


def _final_worlds_picture(trial: HouseRoofTrial) -> np.ndarray:
    demo = trial.demonstration
    panels = [_label(_small(demo.world_after.render()), "demonstration: goal")]
    for frame in FRAMES:
        reproduction = trial.reproductions[frame]
        verdict = "goal reached" if reproduction.success else "WRONG"
        panels.append(_label(_small(reproduction.world_after.render()), f"{frame} frame: {verdict}"))
    return np.hstack(panels)


def _trajectory_figure(path: Path, reproduction: Reproduction) -> None:
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
        line, = top.plot(xyz[:, 0], xyz[:, 1], lw=2, label=f"op {k}: {result.diagnosis}")
        top.plot(*xyz[result.trajectory.segments[1], :2], "o", color=line.get_color())
        top.plot(*xyz[result.trajectory.segments[2], :2], "s", color=line.get_color())
        z_axis.plot(t, xyz[:, 2], color=line.get_color())
        theta_axis.plot(t, np.degrees(theta), color=line.get_color())
        clock = t[-1]
    top.set(xlim=(0, width * PIXEL_SIZE), ylim=((height + 120) * PIXEL_SIZE, 0), xlabel="x (m)", ylabel="y (m)",
            title="hand paths rest → pick (o) → place (□) → rest")
    top.legend(loc="lower left", fontsize=8)
    z_axis.set(ylabel="height z (m)", title="height profile h[1 − |atanh(h0(s − 0.5))/atanh(h0/2)|^κ]")
    theta_axis.set(xlabel="t (s)", ylabel="hand rotation θ (deg)", title="trapezoidal rotation profile")
    figure.tight_layout()
    figure.savefig(path, dpi=90)
    plt.close(figure)


def _markdown(data: dict, trials: list[HouseRoofTrial]) -> str:
    lines = ["# house-roof: VSL's adaptive frames (paper, \"Simulation\")", "",
             f"{data['trials']} trials from seed {data['seed']}: the tutor puts roofs on two bodies and the third "
             "roof below the third body; each trial reproduces it in a new random world with a fixed small "
             "pre-place frame and with the adaptive frame. Judged on the ground truth.", "",
             "| frame | successes | success rate | operations ok | diagnoses | ms per reproduction |",
             "|---|---|---|---|---|---|"]
    for frame in FRAMES:
        f = data[f"{frame}_frame"]
        diagnoses = ", ".join(f"{k}: {v}" for k, v in f["diagnoses"].items())
        lines.append(f"| {frame} | {f['successes']}/{data['trials']} | {100 * f['success_rate']:.1f} % | "
                     f"{f['operations_ok']}/{f['operations']} | {diagnoses} | {f['ms_per_reproduction']} |")
    lines += ["", f"Trial success (adaptive frame): {data['successes']}/{data['trials']} "
              f"({100 * data['success_rate']:.1f} %).", ""]
    if data["failures"]:
        lines += ["## Failures (adaptive frame)", ""] + [f"- seed {f['seed']}: {f['error']}"
                                                       for f in data["failures"][:20]] + [""]
    shown = data["shown_trial"]
    if "demonstration" in shown:
        lines += [f"## Trial {shown['seed']}", "", f"![demonstration]({shown['demonstration']})", "",
                  f"![fixed frame]({shown['matches_fixed']})", "", f"![adaptive frame]({shown['matches_adaptive']})",
                  "", f"![final worlds]({shown['final_worlds']})", "", f"![trajectory]({shown['trajectory']})", ""]
    lines += ["## Trials", "", "| seed | fixed | adaptive | adaptive operations |", "|---|---|---|---|"]
    for t in trials:
        if t.error:
            lines.append(f"| {t.seed} | - | - | {t.error} |")
            continue
        ops = ", ".join(op["diagnosis"] for op in t.results["adaptive"]["operations"])
        lines.append(f"| {t.seed} | {'ok' if t.results['fixed']['success'] else 'wrong'} | "
                     f"{'ok' if t.results['adaptive']['success'] else 'wrong'} | {ops} |")
    return "\n".join(lines) + "\n"


def _square(image: np.ndarray, centre: tuple[float, float], size: int, colour) -> None:
    half = size / 2.0
    cv2.rectangle(image, _int((centre[0] - half, centre[1] - half)), _int((centre[0] + half, centre[1] + half)),
                  colour, 3)


def _small(image: np.ndarray) -> np.ndarray:
    return cv2.resize(image, None, fx=_SCALE, fy=_SCALE, interpolation=cv2.INTER_AREA)


def _label(image: np.ndarray, text: str, origin: tuple[int, int] = (8, 26)) -> np.ndarray:
    image = image.copy()
    cv2.putText(image, text, origin, cv2.FONT_HERSHEY_SIMPLEX, 0.7, (0, 0, 0), 5, cv2.LINE_AA)
    cv2.putText(image, text, origin, cv2.FONT_HERSHEY_SIMPLEX, 0.7, _TEXT, 2, cv2.LINE_AA)
    return image


def _int(point) -> tuple[int, int]:
    return int(round(point[0])), int(round(point[1]))


def command(trials: int, seed: int, workers: int, out: str | None, as_json: bool, faults: bool = False) -> None:
    """``vslsp experiment house-roof``: run the trials with progress on stderr, write the report,
    print the summary (one JSON object with ``as_json``) and exit 0 when every trial succeeded,
    1 otherwise."""
    import sys

    import click
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    from vslsp.errors import InputError
    from vslsp.vsl.tasks import run_trials

    if faults:
        raise InputError("--faults applies to the VSL-SP experiments; house-roof has no execution faults to inject")
    folder = Path(out) if out else Path("out") / "experiments" / "house-roof"
    with Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                  TextColumn("{task.fields[ok]} ok"), console=Console(stderr=True), transient=True) as progress:
        task = progress.add_task("house-roof", total=trials, ok=0)
        done = {"ok": 0}

        def advance(trial: HouseRoofTrial) -> None:
            done["ok"] += trial.success
            progress.update(task, advance=1, ok=done["ok"])

        results = run_trials(trials, seed, workers, on_done=advance)
        progress.update(task, description="house-roof: report")
        data = write_report(folder, results, seed)
    if as_json:
        click.echo(json.dumps({k: v for k, v in data.items() if k != "results"}))
    else:
        fixed, adaptive = data["fixed_frame"], data["adaptive_frame"]
        click.echo(f"house-roof: {data['successes']}/{data['trials']} trials succeeded with the adaptive frame "
                   f"({100 * adaptive['success_rate']:.1f} %), {fixed['successes']} with the fixed frame "
                   f"({100 * fixed['success_rate']:.1f} %); report: {folder}")
        for failure in data["failures"][:10]:
            click.echo(f"  seed {failure['seed']}: {failure['error']}", err=True)
    sys.exit(0 if data["successes"] == data["trials"] else 1)
