"""The reports pages: ``/reports`` (the report folders under the root), ``/reports/REL`` (one: the
summary, the trials with links to their pages, the images, videos, plans, clouds) and
``/reports/REL/trials/SEED`` (one trial: its record, the annotated images in order, the plan and
replans, trajectories, its video, VSL-3D's clouds as an interactive 3-D view)."""

from __future__ import annotations

import json
from pathlib import Path
from urllib.parse import quote

from nicegui import ui

from vslsp.errors import VslspError
from vslsp.studio import files
from vslsp.studio.layout import frame
from vslsp.studio.report_data import read_report, read_trial, report_folders, trial_of

#: The most points a 3-D view draws (a cloud is subsampled evenly beyond it).
MAX_VIEW_POINTS = 20_000
#: The object's points in a labelled cloud (VSL-3D's report clouds: ``labels`` 1).
OBJECT_COLOUR = (0.85, 0.1, 0.1)
#: An object the tutor disturbed (VSL-3D's report clouds with ``--tutor-slips``: ``labels`` 2).
DISTURBED_COLOUR = (1.0, 0.55, 0.0)


def file_link(rel: str) -> str:
    return "/files/" + quote(rel)


def load_cloud(root: Path, rel: str) -> dict | None:
    """A cloud file under the root for the 3-D view: ``points`` (N, 3) centred and scaled to about a
    unit cube, ``colours`` (N, 3) (the labelled object red, one the tutor disturbed orange, the rest
    by height), ``caption``, ``count``;
    None when the file is not a cloud (an ``.npz`` with ``points`` (N, 3): VSL-3D's report clouds,
    :func:`vslsp.vsl3d.pictures.write_clouds`, or an observation, ``CloudObservation.save``)."""
    import numpy as np  # here: the studio starts without it

    try:
        with np.load(files.inside(root, rel), allow_pickle=False) as data:
            points = np.asarray(data["points"], dtype=float)
            labels = np.asarray(data["labels"]) if "labels" in data.files else None
            caption = str(data["caption"]) if "caption" in data.files else ""
    except (OSError, KeyError, ValueError, VslspError):
        return None
    if points.ndim != 2 or points.shape[1] != 3 or not len(points) or not np.isfinite(points).all():
        return None
    if labels is not None and labels.shape != (len(points),):
        labels = None
    step = max(1, -(-len(points) // MAX_VIEW_POINTS))
    points = points[::step]
    labels = labels[::step] if labels is not None else None
    centred = points - (points.max(axis=0) + points.min(axis=0)) / 2.0
    centred = centred / (float(np.abs(centred).max()) or 1.0)
    low, high = float(centred[:, 2].min()), float(centred[:, 2].max())
    heat = (centred[:, 2] - low) / ((high - low) or 1.0)
    colours = np.stack([0.2 + 0.3 * heat, 0.45 + 0.2 * heat, 0.9 - 0.4 * heat], axis=1)
    if labels is not None:
        colours[labels == 1] = OBJECT_COLOUR
        colours[labels == 2] = DISTURBED_COLOUR
    return {
        "points": np.round(centred, 4).tolist(),
        "colours": np.round(colours, 3).tolist(),
        "caption": caption,
        "count": len(points),
    }


def cloud_viewer(root: Path, clouds: list[str]) -> None:
    """One interactive 3-D view (three.js, in NiceGUI's wheel: works offline) of the ``clouds`` (paths
    under the root), the one shown picked from a list; drag to turn, scroll to zoom."""
    loaded = {rel: cloud for rel in clouds if (cloud := load_cloud(root, rel)) is not None}
    if not loaded:
        return
    first = next(iter(loaded))
    with ui.card().classes("cloud-card"):
        ui.label("Point clouds (drag to turn, scroll to zoom; the object red)").classes("text-bold")
        choice = ui.select({rel: Path(rel).name for rel in loaded}, value=first, label="cloud").classes(
            "w-96 pick-cloud"
        )
        caption = ui.label().classes("text-caption cloud-caption")
        with ui.scene(width=720, height=460, grid=False).classes("cloud-view") as view:
            shown = view.point_cloud(loaded[first]["points"], loaded[first]["colours"], point_size=0.015)
            view.move_camera(x=0.8, y=-1.3, z=1.3, look_at_x=0, look_at_y=0, look_at_z=0)

        def show(rel: str) -> None:
            cloud = loaded[rel]
            caption.set_text(f"{rel}: {cloud['count']} points. {cloud['caption']}")
            shown.set_points(cloud["points"], cloud["colours"])
            view.props(f"data-points={cloud['count']}")

        choice.on_value_change(lambda event: show(event.value))
        show(first)


def index_page(root: Path) -> None:
    found = report_folders(root)
    if not found:
        ui.label("no report folders under the root yet: run an experiment")
    for folder in found:
        ui.link(folder, f"/reports/{folder}").classes("report-folder")


def report_page(root: Path, rel: str) -> None:
    """A report folder: the summary table, the trials (each a link to its page), the images in order,
    the videos, the clouds in 3-D, plans and report.md."""
    report = read_report(root, rel)
    summary = report["summary"]
    ui.label(f"{summary.get('experiment')} — {report['folder']}").classes("text-h5")
    plain = {k: v for k, v in summary.items() if isinstance(v, (str, int, float, bool)) or v is None}
    rows = [{"field": k, "value": json.dumps(v) if not isinstance(v, str) else v} for k, v in plain.items()]
    columns = [{"name": k, "label": k, "field": k, "align": "left"} for k in ("field", "value")]
    ui.table(columns=columns, rows=rows).classes("summary-table")
    with ui.row().classes("items-center trial-links"):
        ui.label("Trials:").classes("text-bold")
        for trial in report["trials"]:
            mark = "✓" if trial["success"] else "✗"
            pictures = " 🖼" if trial["pictures"] else ""
            ui.link(f"{mark} seed {trial['seed']}{pictures}", trial["link"]).classes("trial-link").tooltip(
                (trial["error"] or "ok") + ("; with its pictures" if trial["pictures"] else "")
            )
    for image in report["images"]:
        with ui.card().classes("w-full max-w-3xl"):
            ui.label(image).classes("text-caption")
            ui.image(file_link(image)).classes("w-full report-image")
    cloud_viewer(root, report["clouds"])
    for video in report["videos"]:
        ui.video(file_link(video)).classes("max-w-3xl report-video")
    for plan in report["plans"]:
        with ui.expansion(plan).classes("w-full report-plan"):
            ui.code(files.read_small(root, plan))
    if report["markdown"]:
        with ui.expansion("report.md").classes("w-full"):
            ui.markdown(report["markdown"].replace("](", "](/files/" + quote(report["folder"]) + "/"))


def trial_page(root: Path, rel: str, seed: int) -> None:
    """One trial: its outcome, its video, the plan and replans, the clouds in 3-D, the annotated images
    in the report's order (the trajectories among them), its files, operations and whole record."""
    trial = read_trial(root, rel, seed)
    record = trial["record"]
    ui.link(f"← {trial['folder']}", f"/reports/{trial['folder']}").classes("back-link")
    verdict = "succeeded" if record.get("success") else "FAILED"
    ui.label(f"{record.get('experiment')}: trial {seed} {verdict} ({record.get('time_s')} s)").classes(
        "text-h5 trial-title"
    )
    if record.get("error"):
        ui.label(str(record["error"])).classes("text-negative trial-error")
    if trial["pictures"] is None:
        drawn = trial["shown_seed"]
        note = "the report drew no figures" if drawn is None else f"the report drew its figures for trial {drawn} only"
        ui.label(f"{note}; this trial has its record{' and video' if trial['video'] else ''}.").classes(
            "text-grey-7 trial-note"
        )
        draw_button(root, trial["folder"], seed)
    elif trial["check"] is not None:
        check_note(trial["check"])
    if trial["video"]:
        ui.video(file_link(trial["video"])).classes("max-w-3xl trial-video")
    if trial["plans"]:
        ui.label("Plan and replans").classes("text-h6")
        with ui.row().classes("items-start"):
            for plan in trial["plans"]:
                with ui.column().classes("trial-plan gap-0 q-mr-lg"):
                    ui.label(plan["title"]).classes("text-bold")
                    for number, step in enumerate(plan["plan"], start=1):
                        ui.label(f"{number}. ({step})").classes("trial-plan-step")
                    if not plan["plan"]:
                        ui.label("no steps: the goal already holds").classes("text-grey-7")
    cloud_viewer(root, trial["clouds"])
    for number, image in enumerate(trial["images"], start=1):
        with ui.card().classes("w-full max-w-4xl trial-image-card"):
            ui.label(f"{number}. {image['title']}").classes("text-bold trial-image-title")
            if image["caption"]:
                ui.label(str(image["caption"])).classes("text-caption")
            ui.image(file_link(image["file"])).classes("w-full trial-image")
    for item in trial["files"]:
        with ui.expansion(f"{item['title']}: {item['file']}").classes("w-full trial-file"):
            ui.code(files.read_small(root, item["file"]))
    operations = record.get("operations") or []
    if operations:
        with ui.expansion(f"{len(operations)} operations (trajectories, outcomes)").classes("w-full trial-operations"):
            for number, operation in enumerate(operations, start=1):
                with ui.expansion(f"operation {number}"):
                    ui.code(json.dumps(operation, indent=1), language="json")
    with ui.expansion("the trial's record (report.json)").classes("w-full trial-record"):
        ui.code(json.dumps(record, indent=1), language="json")


def draw_button(root: Path, folder: str, seed: int) -> None:
    """ "Draw this trial's pictures": a background job re-runs the trial from its seed
    (:mod:`vslsp.studio.trial_figures`); its state shown every second, the page reloaded when it is done."""
    from vslsp.studio import trial_figures

    with ui.row().classes("items-center"):
        button = ui.button("Draw this trial's pictures").classes("draw-pictures")
        state = ui.label().classes("draw-state")
    error = ui.label().classes("text-negative draw-error")
    picture = ui.image().classes("w-96 live-picture")
    picture.set_visibility(False)
    job: dict[str, str | None] = {"id": None}

    def show(status: dict | None) -> None:
        if status is None:
            return
        job["id"] = status["id"]
        if status["state"] == "done":
            ui.navigate.reload()
            return
        button.set_enabled(status["state"] == "failed")
        error.set_text((status.get("error") or "") if status["state"] == "failed" else "")
        state.set_text(
            f"re-running trial {seed} from its seed to draw its pictures (it goes on if you close the page)…"
            if status["state"] == "running"
            else "drawing failed"
        )
        if status.get("latest"):
            version = (root.resolve() / status["latest"]).stat().st_mtime_ns
            picture.set_source(file_link(status["latest"]) + f"?v={version}")
            picture.set_visibility(True)

    def start() -> None:
        try:
            job_id = trial_figures.start(root, folder, seed)
            show(trial_figures.get(root, job_id))
        except VslspError as refused:
            error.set_text(str(refused))

    def poll() -> None:
        if job["id"] is not None:
            try:
                show(trial_figures.get(root, str(job["id"])))
            except (VslspError, OSError):
                pass

    button.on_click(start)
    show(trial_figures.newest(root, folder, seed))
    ui.timer(1.0, poll)


def check_note(check: dict) -> None:
    """What the re-run that drew these pictures gave: the recorded trial again, or where it differs."""
    if check["matches"]:
        ui.label(
            "Pictures drawn by the studio: the trial re-run from its seed; its record matches the recorded one "
            "(times excepted), so these are this trial's pictures."
        ).classes("text-positive trial-check")
        return
    ui.label(
        "Pictures drawn by the studio, but the re-run's record differs from the recorded one (times excepted): "
        "these pictures may not show the recorded trial."
    ).classes("text-negative trial-check trial-check-differs")
    for difference in check["differences"]:
        ui.label(difference).classes("text-caption trial-difference")


def reports_page(root: Path, rel: str | None) -> None:
    """``/reports``, ``/reports/REL`` or ``/reports/REL/trials/SEED``."""
    frame("Reports")
    if not rel:
        index_page(root)
        return
    try:
        trial = trial_of(root, rel)
        if trial is not None:
            trial_page(root, *trial)
        else:
            report_page(root, rel)
    except VslspError as error:
        ui.label(str(error)).classes("text-negative page-error")
