"""The ground, experiments and reports pages (the author page: :mod:`vslsp.studio.author`)."""

from __future__ import annotations

from pathlib import Path
from urllib.parse import quote

from nicegui import events, ui

from vslsp.errors import VslspError
from vslsp.studio import api, files, reports, runs
from vslsp.studio.board import RunBoard
from vslsp.studio.layout import frame, in_thread
from vslsp.studio.settings import Settings


def _rel_link(rel: str) -> str:
    return "/files/" + quote(rel)


def ground_page(root: Path, pre: str | None, post: str | None, predicates: str | None, settings: Settings) -> None:
    """Pick or drop a pre/post image pair, a predicates file under the root; the overlay, the moved
    object and the true atoms before and after. Paper: "VSL" (getObject by image subtraction)."""
    frame("Ground")
    images = files.listing(root, api.IMAGE_SUFFIXES)
    predicate_files = [p for p in files.listing(root, (".py",)) if "predicate" in Path(p).name]
    unknown = [f"{name} {value}" for name, value in (("pre", pre), ("post", post)) if value and value not in images]
    pre, post = (value if value in images else None for value in (pre, post))
    if predicates and predicates not in predicate_files:
        unknown.append(f"predicates {predicates}")
        predicates = None
    if unknown:
        ui.label(f"not an image or predicates file under the root: {', '.join(unknown)}").classes(
            "text-negative page-error"
        )
    with ui.row().classes("items-end"):
        chosen = {
            "pre": ui.select(images, value=pre, label="pre-action image", with_input=True).classes("w-80 pick-pre"),
            "post": ui.select(images, value=post, label="post-action image", with_input=True).classes("w-80 pick-post"),
        }
        chosen_predicates = ui.select(
            predicate_files, value=predicates, label="predicates file (under the root)", clearable=True
        ).classes("w-80 pick-predicates")
        button = ui.button("Ground").props("id=ground")
        edit = ui.button("Edit predicates").props("flat")

    def uploaded(kind: str):
        async def handle(event: events.UploadEventArguments) -> None:
            content = await event.file.read()
            if len(content) > files.MAX_UPLOAD_BYTES:
                ui.notify("the image is over the upload limit", type="negative")
                return
            name = Path(event.file.name).name
            if Path(name).suffix.lower() not in api.IMAGE_SUFFIXES:
                ui.notify(f"{name}: upload a PNG or JPEG image", type="negative")
                return
            target = files.inside(root, f"{api.UPLOADS}/{name}", must_exist=False)
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(content)
            rel = files.relative(root, target)
            chosen[kind].set_options(sorted({*chosen[kind].options, rel}), value=rel)

        return handle

    async def render() -> None:
        try:
            answer = await in_thread(api.render_scene, root, int(seed.value or 0))
        except VslspError as error:
            ui.notify(str(error), type="negative")
            return
        for select in chosen.values():
            select.set_options(sorted({*select.options, *answer["images"]}), value=select.value)
        ui.notify(f"rendered {', '.join(answer['images'])}")

    with ui.row().classes("items-end"):
        seed = ui.number("scene seed", value=0, min=0, precision=0).classes("w-28")
        ui.button("Render scene", on_click=render).props("id=render flat")
        for kind in ("pre", "post"):
            ui.upload(
                label=f"drop a {kind}-action image", auto_upload=True, max_file_size=files.MAX_UPLOAD_BYTES
            ).on_upload(uploaded(kind)).props("accept=.png,.jpg,.jpeg")
    result = ui.column().classes("w-full ground-result")

    async def ground() -> None:
        request = {"pre": chosen["pre"].value, "post": chosen["post"].value, "predicates": chosen_predicates.value}
        result.clear()
        try:
            answer = await in_thread(api.ground_pair, root, request)  # the API's own function
        except VslspError as error:
            with result:
                ui.label(str(error)).classes("text-negative ground-error")
            return
        with result:
            ui.image(_rel_link(answer["overlay"]) + f"?v={id(answer)}").classes("w-full max-w-4xl overlay")
            far = {True: "far", False: "not far"}
            ui.label(
                f"moved: {answer['object']['name']}, {far[answer['far']['pre']]} -> {far[answer['far']['post']]}, "
                f"action: {answer.get('action') or 'none'}"
            ).classes("moved")
            atoms = answer.get("atoms") or {}
            for when in ("pre", "post"):
                ui.label(f"{when}: {' '.join(atoms.get(when, [])) or '(none true)'}").classes(f"atoms atoms-{when}")

    button.on_click(ground)

    def open_editor() -> None:
        if not chosen_predicates.value:
            ui.notify("choose a predicates file first", type="warning")
            return
        rel = chosen_predicates.value
        with ui.dialog() as dialog, ui.card().classes("w-2/3"):
            editor = ui.codemirror(files.read_small(root, rel), language="Python").classes("w-full h-96")
            if not settings.edit_code:
                editor.props("disable")
                ui.label("read only: the studio writes no Python file unless started with --edit-code").classes(
                    "text-grey-7 code-read-only"
                )

            def save() -> None:
                try:
                    files.write_text(root, rel, editor.value, code=settings.edit_code)
                except VslspError as error:
                    ui.notify(str(error), type="negative")
                    return
                dialog.close()
                ui.notify(f"saved {rel}; ground again to use it")

            ui.button("Save", on_click=save).set_enabled(settings.edit_code)
        dialog.open()

    edit.on_click(open_editor)


def experiments_page(root: Path) -> None:
    """The registered experiments; start a run in the background and watch it (it goes on when the page closes)."""
    from vslsp.tasks import list_tasks

    frame("Experiments")
    entries = [cls().describe() for cls in list_tasks()]
    columns = [
        {"name": k, "label": k, "field": k, "align": "left"} for k in ("name", "system", "paper_section", "options")
    ]
    rows = [{**e, "options": ", ".join(e["options"]) or "-"} for e in entries]
    ui.table(columns=columns, rows=rows, row_key="name").classes("w-full experiments-table")
    with ui.row().classes("items-end"):
        name = ui.select([e["name"] for e in entries], value=entries[0]["name"], label="experiment").classes(
            "w-60 pick-experiment"
        )
        trials = ui.number("trials", value=1, min=1, max=1000, precision=0).classes("w-24")
        seed = ui.number("seed", value=0, min=0, precision=0).classes("w-24")
        workers = ui.number("workers", value=1, min=1, precision=0).classes("w-24")
        backend = ui.select(["local", "ray"], value="local", label="backend").classes("w-24")
        faults = ui.checkbox("faults")
        video = ui.checkbox("video")
    with ui.row().classes("items-end"):
        slips = ui.number("tutor slips (P)", value=None, min=0, max=1, step=0.1).classes("w-32 pick-slips")
        detection = ui.select({None: "default", True: "on", False: "off"}, value=None, label="slip detection")
        method = ui.select(
            {None: "default", "prerejective_ransac": "prerejective_ransac", "sac_ia": "sac_ia", "icp": "icp"},
            value=None,
            label="VSL-3D method",
        ).classes("w-48")
        views = ui.select({None: "default", 1: "1", 2: "2"}, value=None, label="views").classes("w-24")
        intervention = ui.select(
            {None: "default", "by-seed": "by-seed", "none": "none", "first-move": "first-move"},
            value=None,
            label="Hanoi intervention",
        ).classes("w-40")
        planner = ui.input("planner (default: fast-downward)").classes("w-56")
        start = ui.button("Start").props("id=start")

    async def start_run() -> None:
        given = {
            "faults": bool(faults.value),
            "video": bool(video.value),
            "tutor_slips": None if slips.value in (None, "") else float(slips.value),
            "slip_detection": detection.value,
            "method": method.value,
            "views": views.value,
            "intervention": intervention.value,
            "planner": planner.value or None,
        }
        request = {
            "experiment": name.value,
            "trials": int(trials.value or 1),
            "seed": int(seed.value or 0),
            "workers": int(workers.value or 1),
            "backend": backend.value,
            **{k: v for k, v in given.items() if v not in (None, False)},
        }
        try:
            run_id = await in_thread(lambda: {"id": runs.start(root, request)})
        except VslspError as error:
            ui.notify(str(error), type="negative")
            return
        ui.notify(f"queued run {run_id['id']}")
        board.refresh()

    start.on_click(start_run)
    board = RunBoard(root)


def register(root: Path, settings: Settings | None = None) -> None:
    settings = settings or Settings()

    @ui.page("/ground")
    def _ground(pre: str | None = None, post: str | None = None, predicates: str | None = None) -> None:
        ground_page(root, pre, post, predicates, settings)

    @ui.page("/experiments")
    def _experiments() -> None:
        experiments_page(root)

    @ui.page("/reports")
    def _reports_index() -> None:
        reports.reports_page(root, None)

    @ui.page("/reports/{rel:path}")
    def _reports(rel: str) -> None:
        reports.reports_page(root, rel)

    @ui.page("/")
    def _home() -> None:
        ui.navigate.to("/author")
