"""The studio's JSON API under ``/api`` and its files under ``/files`` (docs/studio.md).

Every answer is JSON. Bad input is a 4xx with the CLI's one-line message (``{"error", "exit_code": 2}``):
400 a bad request, 403 a path out of the root, 404 a missing file or run, 413 too large. A task that
fails on good input (no plan, an invalid plan) is a 200 with the CLI's JSON (``"exit_code": 1``).
Heavy work (planning, grounding) runs in a worker thread so the pages stay live.
"""

from __future__ import annotations

import json
from pathlib import Path

from fastapi import APIRouter, FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import FileResponse, JSONResponse
from starlette.concurrency import run_in_threadpool

from vslsp.errors import InputError, VslspError
from vslsp.studio import engine, files, runs, trial_figures
from vslsp.studio.files import MAX_UPLOAD_BYTES, Missing, Outside, inside, relative
from vslsp.studio.guard import Access, Guard, TooLarge
from vslsp.studio.report_data import read_report, read_trial, report_folders, trial_of
from vslsp.studio.settings import Settings

IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg")
UPLOADS = "out/studio/uploads"


def _status(error: VslspError) -> int:
    if isinstance(error, Outside):
        return 403
    if isinstance(error, Missing):
        return 404
    if isinstance(error, TooLarge):
        return 413
    if isinstance(error, (trial_figures.Drawn, files.Conflict)):
        return 409
    return 400 if error.exit_code == 2 else 500


async def _body(request: Request, limit: int = files.MAX_TEXT_CHARS * 3) -> dict:
    raw = await request.body()
    if len(raw) > limit:
        raise TooLarge(f"the request is over {limit // (1024 * 1024)} MiB")
    try:
        data = json.loads(raw or b"{}")
    except (ValueError, UnicodeDecodeError):
        raise InputError("the request body is not JSON; send a JSON object") from None
    if not isinstance(data, dict):
        raise InputError("send a JSON object")
    return data


def _text(data: dict, key: str, required: bool = True) -> str:
    value = data.get(key)
    if value is None and not required:
        return ""
    if not isinstance(value, str):
        raise InputError(f"{key!r} must be text (the {key} file's content)")
    if len(value) > files.MAX_TEXT_CHARS:
        raise TooLarge(f"{key} is over {files.MAX_TEXT_CHARS // 1024} KiB")
    return value


def _name(data: dict, key: str, default: str) -> str:
    value = data.get(key)
    return value if isinstance(value, str) and value and len(value) < 300 else default


def _completion_request(data: dict) -> tuple[str, str | None, str, int, str, str]:
    """``POST /api/complete``'s fields: both texts, the editor (``in``) and the offset ``at`` in it."""
    domain, problem = _text(data, "domain"), _text(data, "problem", required=False) or None
    editor = data.get("in", "domain")
    if editor not in ("domain", "problem"):
        raise InputError(f"'in' must be domain or problem, got {editor!r}")
    at, text = data.get("at"), domain if editor == "domain" else problem or ""
    if not isinstance(at, int) or isinstance(at, bool) or not 0 <= at <= len(text):
        raise InputError(f"'at' must be an offset in the {editor} text (0 to {len(text)}), got {at!r}")
    names = (_name(data, "domain_file", "<domain>"), _name(data, "problem_file", "<problem>"))
    return domain, problem, editor, at, *names


def report_or_trial(root: Path, rel: str) -> dict:
    """``REL`` a report folder (:func:`read_report`), ``REL/trials/SEED`` one of its trials (with ``job``,
    the newest job drawing its pictures, or None), or ``REL/trials/SEED/figures`` that job."""
    drawing = trial_figures.address(rel)
    if drawing is not None and not (inside(root, rel, must_exist=False) / "report.json").is_file():
        folder, seed = drawing
        read_trial(root, folder, seed)  # refused as the trial's page is
        job = trial_figures.newest(root, relative(root, inside(root, folder)), seed)
        if job is None:
            raise Missing(f"{folder}: no pictures drawn or being drawn for trial {seed} (POST to draw them)")
        return job
    trial = trial_of(root, rel)
    if trial is None:
        return read_report(root, rel)
    found = read_trial(root, *trial)
    return {**found, "job": trial_figures.newest(root, found["folder"], trial[1])}


def without_root(message: str, root: Path) -> str:
    """``message`` with the server's own folders (the root, the studio's working folder) left out: an answer
    names files relative to the root only."""
    for folder in sorted({str(root), str(Path.cwd().resolve())}, key=len, reverse=True):
        if len(folder) > 1:
            message = message.replace(folder + "/", "").replace(folder, ".")
    return message


def install(app: FastAPI, root: Path, access: Access | None = None, settings: Settings | None = None) -> None:
    """Add the API and ``/files`` to ``app``, and (with ``access``) the guard in front of all of it
    (:mod:`vslsp.studio.guard`)."""
    root = root.resolve()
    runs.queue(root, (settings or Settings()).max_jobs)
    api = APIRouter(prefix="/api")

    @app.exception_handler(VslspError)
    async def _refused(request: Request, error: VslspError) -> JSONResponse:
        answer = {"error": without_root(str(error), root), "exit_code": error.exit_code}
        return JSONResponse(answer, status_code=_status(error))

    @app.exception_handler(RequestValidationError)
    async def _unreadable(request: Request, error: RequestValidationError) -> JSONResponse:
        problems = error.errors()
        first = problems[0] if problems else {}
        loc = tuple(first.get("loc", ()))
        where = " ".join(str(part) for part in (loc[1:] if loc[:1] in (("query",), ("body",), ("path",)) else loc))
        what = "is missing" if first.get("type") == "missing" else f"is not valid ({first.get('msg', 'bad value')})"
        return JSONResponse({"error": f"the parameter {where or '?'} {what}", "exit_code": 2}, status_code=400)

    if access is not None:
        app.add_middleware(Guard, access=access)

    @api.get("/experiments")
    async def experiments() -> dict:
        from vslsp.tasks import list_tasks

        return {"experiments": [cls().describe() for cls in list_tasks()]}

    @api.get("/list")
    async def listing(kind: str = "pddl") -> dict:
        suffixes = {"pddl": (".pddl",), "image": IMAGE_SUFFIXES, "predicates": (".py",), "plan": (".plan", ".txt")}
        if kind == "reports":
            return {"files": await run_in_threadpool(report_folders, root)}
        if kind not in suffixes:
            raise InputError(f"kind must be one of {', '.join([*suffixes, 'reports'])}, got {kind!r}")
        return {"files": await run_in_threadpool(files.listing, root, suffixes[kind])}

    @api.get("/text")
    async def text(path: str) -> dict:
        content = files.read_small(root, path)
        return {"path": path, "text": content, "version": files.version_of(inside(root, path))}

    @api.post("/save")
    async def save(request: Request) -> dict:
        data = await _body(request)
        path, base, overwrite = data.get("path"), data.get("base"), data.get("overwrite", False)
        if not isinstance(path, str):
            raise InputError("path must name a .pddl, .plan or .txt file under the root")
        if base is not None and not isinstance(base, str) or not isinstance(overwrite, bool):
            raise InputError("base must be the version GET /api/text gave, overwrite true or false")
        content = _text(data, "text")
        if not overwrite:
            files.refuse_unseen(root, path, base)
        written = files.write_text(root, path, content)
        return {"path": relative(root, written), "version": files.version_of(written)}

    @api.post("/check")
    async def check(request: Request) -> dict:
        data = await _body(request)
        return await engine.call(
            "check",
            _text(data, "domain"),
            _text(data, "problem", required=False) or None,
            _name(data, "domain_file", "<domain>"),
            _name(data, "problem_file", "<problem>"),
        )

    @api.post("/plan")
    async def plan(request: Request) -> JSONResponse:
        data = await _body(request)
        args = (_text(data, "domain"), _text(data, "problem"))
        names = (_name(data, "domain_file", "<domain>"), _name(data, "problem_file", "<problem>"))
        try:
            return JSONResponse(await engine.call("plan", *args, *names))
        except VslspError as error:
            if error.exit_code != 1:
                raise
            answer = {"plan": None, "planner": "fast-downward", "error": str(error), "exit_code": 1}
            said = {"conflict": getattr(error, "conflict", None), "reasons": getattr(error, "reasons", [])}
            return JSONResponse({**answer, **said})

    @api.post("/validate")
    async def validate(request: Request) -> dict:
        data = await _body(request)
        args = (_text(data, "domain"), _text(data, "problem"), _text(data, "plan"))
        names = (_name(data, "domain_file", "<domain>"), _name(data, "problem_file", "<problem>"))
        return await engine.call("validate", *args, *names)

    @api.post("/ground")
    async def ground(request: Request) -> dict:
        data = await _body(request)
        return await run_in_threadpool(ground_pair, root, data)

    @api.post("/scene")
    async def scene(request: Request) -> dict:
        data = await _body(request)
        return await run_in_threadpool(render_scene, root, data.get("seed"))

    @api.post("/upload")
    async def upload(request: Request) -> dict:
        declared = int(request.headers.get("content-length") or 0)
        if declared > MAX_UPLOAD_BYTES + 4096:
            raise TooLarge(f"the upload is over {MAX_UPLOAD_BYTES // (1024 * 1024)} MiB, the most an image may be")
        form = await request.form(max_files=1, max_part_size=MAX_UPLOAD_BYTES)
        sent = form.get("file")
        if sent is None or isinstance(sent, str):
            raise InputError("send one image as the multipart field 'file'")
        name = Path(sent.filename or "image.png").name
        if Path(name).suffix.lower() not in IMAGE_SUFFIXES:
            raise InputError(f"{name}: upload a PNG or JPEG image")
        content = await sent.read(MAX_UPLOAD_BYTES + 1)
        if len(content) > MAX_UPLOAD_BYTES:
            raise TooLarge(f"{name} is over {MAX_UPLOAD_BYTES // (1024 * 1024)} MiB, the most an image may be")
        target = inside(root, f"{UPLOADS}/{name}", must_exist=False)
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_bytes(content)
        return {"path": relative(root, target)}

    @api.post("/runs")
    async def start_run(request: Request) -> dict:
        data = await _body(request)
        return {"id": await run_in_threadpool(runs.start, root, data)}

    @api.get("/runs")
    async def all_runs() -> dict:
        found = await run_in_threadpool(runs.listing, root)
        return {"runs": found, "queued": sum(run["state"] == "queued" for run in found)}

    @api.get("/runs/{run_id}")
    async def one_run(run_id: str) -> dict:
        return runs.get(root, run_id)

    @api.post("/runs/{run_id}/cancel")
    async def cancel_run(run_id: str) -> dict:
        return await run_in_threadpool(runs.queue(root).cancel, runs.RUNS, run_id, "run")

    @api.get("/reports/{rel:path}")
    async def report(rel: str) -> dict:
        return await run_in_threadpool(report_or_trial, root, rel)

    @api.post("/reports/{rel:path}")
    async def draw_trial(rel: str) -> dict:
        drawing = trial_figures.address(rel)
        if drawing is None:
            raise Missing(f"POST /api/reports/REL/trials/SEED/figures draws a trial's pictures; {rel} is not one")
        return {"id": await run_in_threadpool(trial_figures.start, root, *drawing)}

    @api.get("/figures/{job_id}")
    async def figure_job(job_id: str) -> dict:
        return trial_figures.get(root, job_id)

    @api.post("/complete")
    async def complete(request: Request) -> dict:
        data = await _body(request)
        return await engine.call("complete", *_completion_request(data))

    @api.post("/navigate")
    async def navigate(request: Request) -> dict:
        data = await _body(request)
        domain, problem, editor, at, *names = _completion_request(data)
        what, new_name = data.get("what"), data.get("new_name")
        if what not in ("definition", "references", "rename", "outline"):
            raise InputError(f"'what' must be definition, references, rename or outline, got {what!r}")
        if new_name is not None and not isinstance(new_name, str):
            raise InputError("'new_name' must be text")
        return await engine.call("navigate", domain, problem, editor, at, what, new_name, *names)

    app.include_router(api)

    @app.get("/files/{rel:path}")
    async def serve(rel: str) -> FileResponse:
        path = inside(root, rel)
        if not path.is_file():
            raise Missing(f"{rel}: not a file")
        return FileResponse(path)


def ground_pair(root: Path, data: dict) -> dict:
    """``vslsp ground --json`` on two images under the root (predicates only from a file under it, run in a
    child process with limits, never in the studio's)."""
    from vslsp.grounding import draw_grounding, ground_with_user_predicates
    from vslsp.vision.image import read_image, write_image

    pre, post = (inside(root, _text(data, key)) for key in ("pre", "post"))
    side = data.get("robot_side", "bottom")
    if side not in ("bottom", "top", "left", "right"):
        raise InputError(f"robot_side must be bottom, top, left or right, got {side!r}")
    pre_image = read_image(pre, f"pre-action image {data['pre']}")
    post_image = read_image(post, f"post-action image {data['post']}")
    # The predicates (the user's Python) only once the images are known good, and in a child process with
    # limits, isolated from the root and from the studio (vslsp.grounding.contained).
    predicates = inside(root, _text(data, "predicates")) if data.get("predicates") else None
    grounding = ground_with_user_predicates(pre_image, post_image, side, predicates)
    overlay = overlay_path(root)
    write_image(overlay, draw_grounding(pre_image, post_image, grounding))
    return {**grounding.to_dict(), "overlay": relative(root, overlay)}


#: Where each grounding's overlay is drawn, relative to the root, and how many of the newest are kept.
OVERLAYS, KEPT_OVERLAYS = "out/studio/ground", 50


def overlay_path(root: Path) -> Path:
    """A new file for one grounding's overlay (``out/studio/ground/overlay-TIME-RANDOM.png``: two requests
    never draw into the same file), the oldest beyond :data:`KEPT_OVERLAYS` removed."""
    import secrets
    import time

    folder = inside(root, OVERLAYS, must_exist=False)
    folder.mkdir(parents=True, exist_ok=True)
    drawn = sorted(folder.glob("overlay-*.png"))
    for old in drawn[: max(0, len(drawn) - KEPT_OVERLAYS + 1)]:
        old.unlink(missing_ok=True)
    stamp = time.strftime("%Y%m%d-%H%M%S", time.gmtime())
    return folder / f"overlay-{stamp}-{secrets.token_hex(4)}.png"


def render_scene(root: Path, seed: object) -> dict:
    """``vslsp scene --seed S`` into ``out/studio/scenes/seed-S`` under the root: ``{"folder", "images"}``."""
    import os
    import subprocess

    if not isinstance(seed, int) or isinstance(seed, bool) or not 0 <= seed <= 2**32 - 1:
        raise InputError(f"seed must be a whole number from 0 to 4294967295, got {seed!r}")
    import tempfile

    folder = inside(root, f"out/studio/scenes/seed-{seed}", must_exist=False)
    done = subprocess.run(
        runs.isolated_python("vslsp", "scene", "--seed", str(seed), "--out", str(folder)),
        capture_output=True,
        text=True,
        timeout=300,
        cwd=tempfile.gettempdir(),  # never the root: nothing under it is imported
        stdin=subprocess.DEVNULL,
        env={k: v for k, v in os.environ.items() if k not in runs.NOT_INHERITED},
    )
    if done.returncode != 0:
        lines = done.stderr.strip().splitlines() or ["the scene could not be rendered"]
        raise InputError(lines[-1].removeprefix("error: "))
    images = sorted(relative(root, p) for p in folder.glob("*.png"))
    return {"folder": relative(root, folder), "images": images}
