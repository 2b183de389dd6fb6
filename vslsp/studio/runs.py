"""Experiment runs started from the studio: each in its own process (:mod:`vslsp.studio.worker`),
started in a new session so that it goes on when the page, or the studio, is closed. At most
``--max-runs`` runs and picture jobs run at once (:class:`Queue`); the others wait, ``queued``, in
the order they came, and start as one ends. A run is cancelled from the page or ``POST
/api/runs/ID/cancel``: a queued one never starts; a running one is sent SIGTERM, stops its trials,
writes the report of those that finished and ends ``cancelled`` (SIGKILL to its process group when
it has not ended after :data:`CANCEL_GRACE_S`). Ended children are reaped. A run lives in
``ROOT/out/studio/runs/ID/``: ``status.json`` (its request and progress), ``live.png`` (the newest view
of a camera of its trials, :mod:`vslsp.sim.live`) and ``report/`` (the report folder, as ``vslsp experiment
--out`` writes it)."""

from __future__ import annotations

import json
import os
import re
import secrets
import signal
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

from vslsp.errors import InputError
from vslsp.studio.files import Missing

#: Where the runs live, relative to the root.
RUNS = "out/studio/runs"
#: Where the jobs drawing a trial's pictures live (:mod:`vslsp.studio.trial_figures`).
FIGURES = "out/studio/figures"
#: The picture the run's trials publish (:mod:`vslsp.sim.live`), in the run's folder.
LIVE = "live.png"
_ID = re.compile(r"^[0-9]{8}-[0-9]{6}-[0-9a-f]{6}$")
#: The states of a job that has ended.
ENDED = ("done", "failed", "cancelled")
#: How long a cancelled job may take to stop and write its report before its process group is killed.
CANCEL_GRACE_S = 20.0
#: The file in a job's folder that says the user cancelled it (see :func:`request_cancel`).
CANCEL_MARK = "cancel-requested"
#: The experiment options a run request may set (the fields of ``vslsp experiment``'s options).
FIELDS = (
    "experiment",
    "trials",
    "seed",
    "workers",
    "backend",
    "faults",
    "video",
    "tutor_slips",
    "slip_detection",
    "method",
    "views",
    "intervention",
    "planner",
)


def write_status(path: Path, data: dict[str, Any]) -> None:
    """Replace a job's status file at once (a reader never sees half of it)."""
    from vslsp.outputs import write_text

    write_text(path, json.dumps(data))


def request_cancel(folder: Path) -> None:
    """Mark the job in ``folder`` as cancelled by the user. The mark is a file of its own
    (:data:`CANCEL_MARK`), never a field of the status file: the worker rewrites its status from its
    own copy, and a field the studio added would be lost by a write that raced it (a job killed by
    the SIGTERM that followed would then read as failed, not cancelled)."""
    from vslsp.outputs import write_text

    write_text(folder / CANCEL_MARK, "")


def cancel_requested(folder: Path, status: dict[str, Any]) -> bool:
    """Whether the user asked to cancel the job in ``folder`` (its mark, or the status field an
    earlier studio wrote)."""
    return (folder / CANCEL_MARK).exists() or bool(status.get("cancel_requested"))


def _integer(request: dict, key: str, default: int, low: int, high: int) -> int:
    value = request.get(key, default)
    if not isinstance(value, int) or isinstance(value, bool) or not low <= value <= high:
        raise InputError(f"{key} must be a whole number from {low} to {high}, got {value!r}")
    return value


def _choice(request: dict, key: str, kinds: type | tuple[type, ...], what: str) -> Any:
    value = request.get(key)
    if value is None:
        return None
    if not isinstance(value, kinds) or isinstance(value, bool) != (kinds is bool):
        raise InputError(f"{key} must be {what}, got {value!r}")
    return value


def checked(request: Any) -> dict:
    """The run request with its defaults, or InputError (found before any trial runs, as the CLI's). The
    fields are ``vslsp experiment``'s options: ``experiment``, ``trials``, ``seed``, ``workers``, ``backend``,
    ``faults``, ``video``, ``tutor_slips``, ``slip_detection``, ``method``, ``views``, ``intervention``,
    ``planner``."""
    from vslsp.tasks import get_task

    if not isinstance(request, dict):
        raise InputError('send a JSON object such as {"experiment": "house-roof", "trials": 1}')
    name = request.get("experiment")
    if not isinstance(name, str) or not name:
        raise InputError("name an experiment (GET /api/experiments lists them)")
    unknown = set(request) - set(FIELDS)
    if unknown:
        raise InputError(f"unknown field {sorted(unknown)[0]!r}; give {', '.join(FIELDS)}")
    backend = request.get("backend", "local")
    if backend not in ("local", "ray"):
        raise InputError(f"backend must be local or ray, got {backend!r}")
    options = {
        "faults": _choice(request, "faults", bool, "true or false") or False,
        "video": _choice(request, "video", bool, "true or false") or False,
        "tutor_slips": _choice(request, "tutor_slips", (int, float), "a probability from 0 to 1"),
        "slip_detection": _choice(request, "slip_detection", bool, "true or false"),
        "method": _choice(request, "method", str, "a match-finding method's name"),
        "views": _choice(request, "views", int, "1 or 2"),
        "intervention": _choice(request, "intervention", str, "by-seed, none or first-move"),
        "planner": _choice(request, "planner", str, "a planner's name"),
    }
    slips = options["tutor_slips"]
    if slips is not None and not 0 <= slips <= 1:  # NaN fails this too
        raise InputError(f"tutor_slips must be a probability from 0 to 1, got {slips!r}")
    if options["views"] is not None and options["views"] not in (1, 2):
        raise InputError(f"views must be 1 or 2, got {options['views']!r}")
    get_task(name, **task_options(options, tempfile.gettempdir()))  # an unknown experiment, an option it does not take
    return {
        "experiment": name,
        "trials": _integer(request, "trials", 1, 1, 1000),
        "seed": _integer(request, "seed", 0, 0, 2**32 - 1),
        "workers": _integer(request, "workers", 1, 1, max(1, os.cpu_count() or 1)),
        "backend": backend,
        **options,
    }


def task_options(request: dict, report_folder: str) -> dict[str, Any]:
    """The options of ``get_task`` for a checked request (``video``: the report folder it films into)."""
    options = {
        key: request.get(key) for key in ("faults", "tutor_slips", "slip_detection", "method", "views", "intervention")
    }
    return {**options, "planner": request.get("planner"), "video": report_folder if request.get("video") else None}


def start(root: Path, request: Any) -> str:
    """Start a run of the (checked) request; returns its id."""
    request = checked(request)
    status = {"state": "running", "done": 0, "total": request["trials"], "successes": 0, "report": None}
    return launch(root, RUNS, {**status, "request": request})


def launch(root: Path, base: str, status: dict) -> str:
    """Queue a job of the studio's worker (:mod:`vslsp.studio.worker`) in ``ROOT/base/ID/`` with ``status``
    (its ``kind`` and ``request``); returns the id. It starts at once when fewer than the queue's limit of
    jobs run (:class:`Queue`), else when one ends."""
    job_id = time.strftime("%Y%m%d-%H%M%S", time.gmtime()) + "-" + secrets.token_hex(3)
    folder = root.resolve() / base / job_id
    folder.mkdir(parents=True)
    status = {**status, "state": "queued", "id": job_id, "folder": f"{base}/{job_id}", "queued_at": time.time()}
    write_status(folder / "status.json", status)
    queue(root).pump()
    return job_id


def isolated_python(module: str, *args: str) -> list[str]:
    """The command running ``python -m module args`` as a child of the studio: this Python, isolated
    (``-I``: neither the working folder, nor PYTHONPATH, nor the user's site folder on its path, so that
    no file under the root, such as a ``vslsp/`` folder, stands in for the installed package), importing
    vslsp from where this process did."""
    package_parent = str(Path(__file__).resolve().parents[2])
    bootstrap = (
        "import sys, runpy; sys.path.insert(0, sys.argv.pop(1)); "
        f"runpy.run_module({module!r}, run_name='__main__', alter_sys=True)"
    )
    return [sys.executable, "-I", "-c", bootstrap, package_parent, *args]


def worker_command(status_path: Path) -> list[str]:
    """The command of a job's process (:func:`isolated_python` of :mod:`vslsp.studio.worker`)."""
    return isolated_python("vslsp.studio.worker", str(status_path))


#: Environment variables a job does not inherit (the studio's secret, if it was given there).
NOT_INHERITED = ("VSLSP_STUDIO_TOKEN",)


def _start(root: Path, base: str, job_id: str) -> subprocess.Popen:
    """Start the queued job's process, in a new session (it goes on when the page or the studio is
    closed), from a working folder of its own (never the root); its trials' cameras publish their views
    to ``live.png``."""
    from vslsp.sim.live import ENV

    folder = root.resolve() / base / job_id
    path = folder / "status.json"
    status = json.loads(path.read_text())
    status.update(state="running", started=time.time(), root=str(root.resolve()))
    write_status(path, status)
    env = {k: v for k, v in os.environ.items() if k not in NOT_INHERITED}
    with open(folder / "log.txt", "wb") as log:
        return subprocess.Popen(
            worker_command(path),
            cwd=tempfile.gettempdir(),
            env={**env, ENV: str(folder / LIVE)},
            stdin=subprocess.DEVNULL,
            stdout=log,
            stderr=subprocess.STDOUT,
            start_new_session=True,
        )


class Queue:
    """The jobs (runs and picture jobs) of one root: at most ``limit`` run at once, the others wait in the
    order they were queued. :meth:`pump` reaps the children that ended and starts what fits; it runs on
    every request that touches jobs and twice a second in a thread of its own while any job waits or runs."""

    def __init__(self, root: Path, limit: int) -> None:
        self.root, self.limit = root.resolve(), limit
        self.children: dict[str, subprocess.Popen] = {}
        self.ended: dict[str, int] = {}  # the exit codes of the children reaped
        self.lock = threading.RLock()
        self.thread: threading.Thread | None = None

    def bases(self) -> tuple[str, ...]:
        return (RUNS, FIGURES)

    def jobs(self) -> list[tuple[str, str, dict]]:
        """(base, id, status) of every job under the root that has not ended, oldest first."""
        found = []
        for base in self.bases():
            for job_id in job_ids(self.root, base, limit=10_000):
                try:
                    status = json.loads((self.root / base / job_id / "status.json").read_text())
                except (OSError, ValueError):
                    continue
                if status.get("state") not in ENDED:
                    found.append((base, job_id, status))
        return sorted(found, key=lambda job: (float(job[2].get("queued_at") or 0), job[1]))

    def pump(self) -> None:
        with self.lock:
            for job_id, child in list(self.children.items()):
                if child.poll() is not None:  # reaped: no zombie is left
                    self.ended[job_id] = child.returncode
                    del self.children[job_id]
            pending = self.jobs()
            running = [j for j in pending if j[2].get("state") != "queued" and self.alive(j[1], j[2])]
            waiting = [j for j in pending if j[2].get("state") == "queued"]
            for base, job_id, _status in waiting[: max(0, self.limit - len(running))]:
                self.children[job_id] = _start(self.root, base, job_id)
            if (self.children or waiting) and (self.thread is None or not self.thread.is_alive()):
                self.thread = threading.Thread(target=self._watch, name="vslsp-studio-queue", daemon=True)
                self.thread.start()

    def _watch(self) -> None:
        while True:
            time.sleep(0.5)
            self.pump()
            with self.lock:
                if not self.children and not any(j[2].get("state") == "queued" for j in self.jobs()):
                    return

    def alive(self, job_id: str, status: dict) -> bool:
        child = self.children.get(job_id)
        if child is not None:
            return child.poll() is None
        if job_id in self.ended:
            return False
        pid = status.get("pid")
        if not isinstance(pid, int):
            return "started" in status and time.time() - float(status["started"]) < 30  # starting
        try:
            os.kill(pid, 0)  # a job started by an earlier studio: is its process still there?
        except OSError:
            return False
        return True

    def position(self, job_id: str) -> int | None:
        """The job's place in the queue (1: next to start), None when it is not waiting."""
        waiting = [j[1] for j in self.jobs() if j[2].get("state") == "queued"]
        return waiting.index(job_id) + 1 if job_id in waiting else None

    def cancel(self, base: str, job_id: str, what: str) -> dict:
        """Cancel a queued job (it never starts) or a running one (SIGTERM: it stops its trials, keeps
        the finished ones in its report; its process group is killed after :data:`CANCEL_GRACE_S`)."""
        with self.lock:
            status = read_job(self.root, base, job_id, what)
            path = self.root / base / job_id / "status.json"
            if status["state"] in ENDED:
                raise InputError(f"the {what} {job_id} has ended already ({status['state']})")
            if status["state"] == "queued":
                write_status(path, {**json.loads(path.read_text()), "state": "cancelled", "error": "cancelled"})
                return read_job(self.root, base, job_id, what)
            child = self.children.get(job_id)
            pid = child.pid if child is not None else status.get("pid")
            request_cancel(path.parent)
            if isinstance(pid, int):
                try:
                    os.kill(pid, signal.SIGTERM)
                except OSError:
                    pass
                threading.Thread(target=self._kill_later, args=(pid, base, job_id), daemon=True).start()
            return {**status, "state": "cancelling"}

    def _kill_later(self, pid: int, base: str, job_id: str) -> None:
        ends = time.monotonic() + CANCEL_GRACE_S
        child = self.children.get(job_id)
        while time.monotonic() < ends:
            if child is not None and child.poll() is not None:
                break
            if child is None and not self.alive(job_id, {"pid": pid}):
                break
            time.sleep(0.1)
        try:
            os.killpg(pid, signal.SIGKILL)  # whatever of its group is left (its workers, a planner)
        except OSError:
            pass
        self.pump()


#: The queue of each root served by this process.
QUEUES: dict[Path, Queue] = {}
#: How many jobs a root's queue runs at once unless the studio was told otherwise (``--max-runs``).
DEFAULT_LIMIT = 2


def queue(root: Path, limit: int | None = None) -> Queue:
    """The job queue of ``root`` (made with ``limit``, or :data:`DEFAULT_LIMIT`, when first asked for)."""
    key = root.resolve()
    if key not in QUEUES:
        QUEUES[key] = Queue(key, limit or DEFAULT_LIMIT)
    elif limit is not None:
        QUEUES[key].limit = limit
    return QUEUES[key]


def get(root: Path, run_id: str) -> dict:
    """The run's ``state`` (running, done, failed), ``done``, ``total``, ``successes``, ``report`` (the
    report folder relative to the root, when done), ``error`` (when failed), ``latest`` (its newest
    picture relative to the root, or None)."""
    status = read_job(root, RUNS, run_id, "run")
    keys = ("id", "state", "done", "total", "successes", "report", "error", "request")
    found = {**{key: status.get(key) for key in keys}, "latest": latest_picture(root, run_id)}
    return {**found, "position": queue(root).position(run_id) if status["state"] == "queued" else None}


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
    if status.get("state") in (*ENDED, "queued"):
        return status
    if not queue(root).alive(job_id, status):
        time.sleep(0.2)  # the worker may have written its last status as it ended
        status = json.loads(path.read_text())
        if status.get("state") not in ENDED and cancel_requested(path.parent, status):
            status.update(state="cancelled", error="cancelled before any trial finished")
        elif status.get("state") not in ENDED:
            status.update(state="failed", error=f"the {what}'s process ended before it finished (see its log.txt)")
    if status.get("state") not in ENDED:
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
