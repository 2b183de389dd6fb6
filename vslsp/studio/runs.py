"""Experiment runs started from the studio: each in its own process (:mod:`vslsp.studio.worker`),
started in a new session so that it goes on when the page, or the studio, is closed. A run lives in
``ROOT/out/studio/runs/ID/``: ``status.json`` (its request and progress), ``live.png`` (the newest view
of a camera of its trials, :mod:`vslsp.sim.live`) and ``report/`` (the report folder, as ``vslsp experiment
--out`` writes it)."""

from __future__ import annotations

import json
import os
import re
import secrets
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

from vslsp.errors import InputError
from vslsp.studio.files import Missing

#: Where the runs live, relative to the root.
RUNS = "out/studio/runs"
#: The picture the run's trials publish (:mod:`vslsp.sim.live`), in the run's folder.
LIVE = "live.png"
_ID = re.compile(r"^[0-9]{8}-[0-9]{6}-[0-9a-f]{6}$")


def write_status(path: Path, data: dict[str, Any]) -> None:
    """Replace a job's status file at once (a reader never sees half of it)."""
    from vslsp.outputs import write_text

    write_text(path, json.dumps(data))


def _integer(request: dict, key: str, default: int, low: int, high: int) -> int:
    value = request.get(key, default)
    if not isinstance(value, int) or isinstance(value, bool) or not low <= value <= high:
        raise InputError(f"{key} must be a whole number from {low} to {high}, got {value!r}")
    return value


def checked(request: Any) -> dict:
    """The run request with its defaults, or InputError (found before any trial runs, as the CLI's)."""
    from vslsp.tasks import get_task

    if not isinstance(request, dict):
        raise InputError('send a JSON object such as {"experiment": "house-roof", "trials": 1}')
    name = request.get("experiment")
    if not isinstance(name, str) or not name:
        raise InputError("name an experiment (GET /api/experiments lists them)")
    unknown = set(request) - {"experiment", "trials", "seed", "workers", "backend", "faults"}
    if unknown:
        raise InputError(
            f"unknown field {sorted(unknown)[0]!r}; give experiment, trials, seed, workers, backend, faults"
        )
    backend = request.get("backend", "local")
    if backend not in ("local", "ray"):
        raise InputError(f"backend must be local or ray, got {backend!r}")
    faults = request.get("faults", False)
    if not isinstance(faults, bool):
        raise InputError(f"faults must be true or false, got {faults!r}")
    get_task(name, faults=faults)  # an unknown experiment or an option it does not take: InputError
    return {
        "experiment": name,
        "trials": _integer(request, "trials", 1, 1, 1000),
        "seed": _integer(request, "seed", 0, 0, 2**32 - 1),
        "workers": _integer(request, "workers", 1, 1, max(1, os.cpu_count() or 1)),
        "backend": backend,
        "faults": faults,
    }


def start(root: Path, request: Any) -> str:
    """Start a run of the (checked) request; returns its id."""
    request = checked(request)
    status = {"state": "running", "done": 0, "total": request["trials"], "successes": 0, "report": None}
    return launch(root, RUNS, {**status, "request": request})


def launch(root: Path, base: str, status: dict) -> str:
    """Start a job of the studio's worker (:mod:`vslsp.studio.worker`) in ``ROOT/base/ID/`` with ``status``
    (its ``kind`` and ``request``); returns the id. The job is its own process in a new session: it goes
    on when the page, or the studio, is closed; its trials' cameras publish their views to ``live.png``."""
    job_id = time.strftime("%Y%m%d-%H%M%S", time.gmtime()) + "-" + secrets.token_hex(3)
    folder = root.resolve() / base / job_id
    folder.mkdir(parents=True)
    status = {**status, "id": job_id, "folder": f"{base}/{job_id}", "started": time.time()}
    path = folder / "status.json"
    write_status(path, status)
    from vslsp.sim.live import ENV

    with open(folder / "log.txt", "wb") as log:
        process = subprocess.Popen(
            [sys.executable, "-m", "vslsp.studio.worker", str(path)],
            cwd=root.resolve(),
            env={**os.environ, ENV: str(folder / LIVE)},  # the trials' cameras publish their newest view there
            stdin=subprocess.DEVNULL,
            stdout=log,
            stderr=subprocess.STDOUT,
            start_new_session=True,  # not ended with the studio's terminal: the run goes on
        )
    _children[job_id] = process
    return job_id


_children: dict[str, subprocess.Popen] = {}


def get(root: Path, run_id: str) -> dict:
    """The run's ``state`` (running, done, failed), ``done``, ``total``, ``successes``, ``report`` (the
    report folder relative to the root, when done), ``error`` (when failed), ``latest`` (its newest
    picture relative to the root, or None)."""
    status = read_job(root, RUNS, run_id, "run")
    keys = ("id", "state", "done", "total", "successes", "report", "error", "request")
    return {**{key: status.get(key) for key in keys}, "latest": latest_picture(root, run_id)}


def read_job(root: Path, base: str, job_id: str, what: str) -> dict:
    """The status of the job ``job_id`` in ``ROOT/base``, its ``state`` running, done or failed (failed
    when its process ended without saying so); :class:`Missing` for an unknown id."""
    if not _ID.match(job_id):
        raise Missing(f"no {what} {job_id!r}")
    path = root.resolve() / base / job_id / "status.json"
    try:
        status = json.loads(path.read_text())
    except (OSError, ValueError):
        raise Missing(f"no {what} {job_id!r}") from None
    if status.get("state") not in ("done", "failed") and not _alive(job_id, status.get("pid")):
        time.sleep(0.2)  # the worker may have written its last status as it ended
        status = json.loads(path.read_text())
        if status.get("state") not in ("done", "failed"):
            status.update(state="failed", error=f"the {what}'s process ended before it finished (see its log.txt)")
    if status.get("state") not in ("done", "failed"):
        status["state"] = "running"
    return status


def job_ids(root: Path, base: str, limit: int = 50) -> list[str]:
    """The ids of the jobs in ``ROOT/base``, newest first (at most ``limit``)."""
    folder = root.resolve() / base
    found = sorted((p.name for p in folder.iterdir() if _ID.match(p.name)), reverse=True) if folder.is_dir() else []
    return found[:limit]


def latest_picture(root: Path, run_id: str, base: str = RUNS) -> str | None:
    """The job's newest picture, relative to the root: the view its trial's cameras published last
    (``live.png``) or, once the report is being written, its newest figure."""
    folder = root.resolve() / base / run_id
    found = [folder / LIVE, *(folder / "report").glob("**/*.png")]
    dated = []
    for path in found:
        try:
            dated.append((path.stat().st_mtime_ns, path))
        except OSError:
            continue
    return max(dated)[1].relative_to(root.resolve()).as_posix() if dated else None


def listing(root: Path) -> list[dict]:
    """Every run under the root, newest first."""
    runs = []
    for run_id in job_ids(root, RUNS):
        try:
            runs.append(get(root, run_id))
        except InputError:
            continue
    return runs


def _alive(run_id: str, pid: Any) -> bool:
    child = _children.get(run_id)
    if child is not None:
        return child.poll() is None
    if not isinstance(pid, int):
        return False
    try:
        os.kill(pid, 0)  # a run started by an earlier studio: is its process still there?
    except OSError:
        return False
    return True
