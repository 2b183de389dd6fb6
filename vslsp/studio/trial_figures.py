"""Drawing the pictures of any trial of a report: a report draws its figures for one trial
(``shown_trial``); the studio draws another's on request by re-running it from its seed (trials are
deterministic) in a background job (:mod:`vslsp.studio.runs`, :mod:`vslsp.studio.worker`: it goes on
when the page is closed).

The job runs the trial with the options the report recorded, draws the experiment's own figures
(:meth:`vslsp.tasks.Task.figures`, the report's pictures) into ``trials/SEED/`` of the report folder
(never over the report's own files; each file written whole, :mod:`vslsp.outputs`) and lists them in
``trials/SEED/figures.json`` as ``shown_trial`` lists the report's, with the check of the re-run: its
record against the recorded one, times excepted (:func:`vslsp.tasks.records.without_times`, as the
report's own figure re-run is checked), ``matches`` and the first ``differences``.
A job lives in ``ROOT/out/studio/figures/ID/`` (``status.json``, ``log.txt``, ``live.png``).
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

from vslsp.errors import InputError
from vslsp.studio import runs
from vslsp.studio.files import Missing, inside, relative
from vslsp.studio.report_data import DRAWN, TRIAL_FOLDER, read_summary

#: Where the figure jobs live, relative to the root.
FIGURES = runs.FIGURES
#: ``REL/trials/SEED/figures``: the pictures of one trial of the report folder REL.
ADDRESS = re.compile(r"^(?P<folder>.+?)/trials/(?P<seed>[0-9]{1,10})/figures/?$")
#: The options a report records in its summary (the others, ``--skills``, ``--predicates``,
#: ``--planner``, are not recorded: a re-run without them is told apart by the record check).
RECORDED_OPTIONS: dict[str, type | tuple[type, ...]] = {
    "faults": bool,
    "method": str,
    "tutor_slips": (int, float),  # the summary's own keys, written by the tasks that take them
    "slip_detection": bool,
    "views": int,
    "intervention": str,
}
#: The options a summary records under a key of another name (tower-of-hanoi's ``intervention`` is
#: the tally of the trials the user intervened in).
RECORDED_AS = {"intervention": "intervention_choice"}
#: The differences a check keeps.
MAX_DIFFERENCES = 20


class Drawn(InputError):
    """The trial has its pictures already (HTTP 409)."""


def address(rel: str) -> tuple[str, int] | None:
    """``(folder, seed)`` when ``rel`` is ``FOLDER/trials/SEED/figures``."""
    found = ADDRESS.match(rel)
    return (found["folder"], int(found["seed"])) if found else None


def checked(root: Path, rel: str, seed: int) -> dict:
    """The request to draw trial ``seed`` of the report folder ``rel``, or an InputError found before
    any work: a path out of the root (:class:`~vslsp.studio.files.Outside`), no such report or trial
    (:class:`Missing`), a report of an unknown experiment, a trial with its pictures (:class:`Drawn`)."""
    from vslsp.tasks import get_task, task_class

    folder, summary = read_summary(root, rel)
    report = relative(root, folder)
    if not any(isinstance(r, dict) and r.get("seed") == seed for r in summary.get("results") or []):
        raise Missing(f"{report}: no trial with seed {seed} in its report.json")
    shown = summary.get("shown_trial")
    if isinstance(shown, dict) and shown.get("seed") == seed:
        raise Drawn(f"{report}: the report drew trial {seed}'s pictures itself; they are on its page")
    name = summary.get("experiment")
    if not isinstance(name, str):
        raise InputError(f"{report}/report.json names no experiment; only a report of vslsp experiment can be re-run")
    options = recorded_options(root, folder, summary, {o.value for o in task_class(name).options})
    get_task(name, **options)  # an unknown experiment or a recorded option it does not take: InputError
    target = inside(root, f"{report}/{TRIAL_FOLDER.format(seed=seed)}", must_exist=False)
    if (target / DRAWN).is_file():
        raise Drawn(f"{report}: trial {seed}'s pictures are drawn already ({relative(root, target)})")
    if target.exists() and not target.is_dir():
        raise InputError(f"{relative(root, target)} is a file; the studio draws a trial's pictures into that folder")
    return {"report": report, "seed": seed, "experiment": name, "options": options}


def recorded_options(root: Path, folder: Path, summary: dict, takes: set[str]) -> dict[str, Any]:
    """The options of the run that wrote the report, as far as it recorded them: the summary's
    ``faults`` and ``method`` (VSL-SP, VSL-3D), ``tutor_slips``, ``slip_detection``, ``views`` and
    ``intervention_choice`` (tower-of-hanoi), or a studio run's request."""
    found = {
        key: summary[RECORDED_AS.get(key, key)]
        for key, kind in RECORDED_OPTIONS.items()
        if key in takes and isinstance(summary.get(RECORDED_AS.get(key, key)), kind)
    }
    status = folder.parent / "status.json"  # a studio run: out/studio/runs/ID/report
    if folder.name == "report" and folder.parent.parent == root.resolve() / runs.RUNS and status.is_file():
        try:
            request = json.loads(status.read_text()).get("request") or {}
        except (OSError, ValueError):
            request = {}
        if "faults" in takes and isinstance(request.get("faults"), bool):
            found["faults"] = request["faults"]
    # a flag off is no option (faults); the slip detection off is (the paper's VSL, a baseline)
    return {key: value for key, value in found.items() if value is not False or key == "slip_detection"}


def start(root: Path, rel: str, seed: int) -> str:
    """Start drawing trial ``seed`` of the report ``rel`` (checked first); returns the job's id (the
    running job's when one is drawing this trial already)."""
    request = checked(root, rel, seed)
    running = newest(root, request["report"], seed)
    if running is not None and running["state"] == "running":
        return str(running["id"])
    return runs.launch(root, FIGURES, {"kind": "figures", "state": "running", "request": request})


def get(root: Path, job_id: str) -> dict:
    """A job's ``id``, ``state`` (running, done, failed), ``report``, ``seed``, ``folder`` (the trial's
    pictures relative to the root, when done), ``matches``, ``differences``, ``error``, ``latest`` (its
    newest picture while it runs)."""
    status = runs.read_job(root, FIGURES, job_id, "figure job")
    request = status.get("request") or {}
    return {
        "id": status.get("id"),
        "state": status["state"],
        "report": request.get("report"),
        "seed": request.get("seed"),
        "folder": status.get("pictures"),
        "matches": status.get("matches"),
        "differences": status.get("differences"),
        "error": status.get("error"),
        "latest": runs.latest_picture(root, job_id, FIGURES) if status["state"] == "running" else None,
    }


def newest(root: Path, report: str, seed: int) -> dict | None:
    """The newest job that drew (or draws) trial ``seed`` of the report folder ``report``, or None."""
    for job_id in runs.job_ids(root, FIGURES, limit=200):
        try:
            request = json.loads((root.resolve() / FIGURES / job_id / "status.json").read_text()).get("request")
        except (OSError, ValueError):
            continue
        if isinstance(request, dict) and (request.get("report"), request.get("seed")) == (report, seed):
            return get(root, job_id)
    return None


def draw(root: Path, request: dict) -> dict:
    """In the job's process: re-run the trial, draw its pictures into ``trials/SEED/`` of the report,
    check its record against the recorded one; the status fields ``pictures``, ``matches``, ``differences``."""
    from vslsp.outputs import lock_folder, write_text
    from vslsp.tasks import get_task, run_one

    report, seed = request["report"], request["seed"]
    checked(root, report, seed)  # the report may have changed since the request
    folder, summary = read_summary(root, report)
    target = inside(root, f"{report}/{TRIAL_FOLDER.format(seed=seed)}", must_exist=False)
    target.mkdir(parents=True, exist_ok=True)
    lock_folder(target, "the trial's pictures")
    task = get_task(request["experiment"], **request["options"])
    again = run_one(task, seed, keep=True)
    files = task.figures(target, again) if again.artefacts is not None else {}
    recorded = next(r for r in summary["results"] if isinstance(r, dict) and r.get("seed") == seed)
    found = differences(comparable(recorded), comparable(again.to_dict()))
    drawn = {
        "seed": seed,
        "success": again.success,
        **files,
        "matches": not found,
        "differences": found,
        "options": request["options"],
    }
    write_text(target / DRAWN, json.dumps(drawn, indent=2) + "\n")
    return {"pictures": relative(root, target), "matches": not found, "differences": found}


def comparable(record: dict) -> Any:
    """A trial's record as JSON, less its times (:func:`vslsp.tasks.records.without_times`) and its
    video (the re-run is not filmed; filming changes nothing in the trial)."""
    from vslsp.tasks.records import without_times

    plain = json.loads(json.dumps(record))
    plain.pop("video", None)
    return without_times(plain)


def differences(recorded: Any, again: Any, where: str = "") -> list[str]:
    """Where two JSON values differ (``path: recorded X, re-run Y``), at most :data:`MAX_DIFFERENCES`."""
    if isinstance(recorded, dict) and isinstance(again, dict):
        found = []
        for key in [*recorded, *(k for k in again if k not in recorded)]:
            inner = f"{where}.{key}" if where else str(key)
            if key not in again or key not in recorded:
                found.append(f"{inner}: {'only in the recorded one' if key in recorded else 'only in the re-run'}")
            else:
                found += differences(recorded[key], again[key], inner)
            if len(found) >= MAX_DIFFERENCES:
                return found[:MAX_DIFFERENCES]
        return found
    if isinstance(recorded, list) and isinstance(again, list) and len(recorded) == len(again):
        found = []
        for index, (one, other) in enumerate(zip(recorded, again, strict=True)):
            found += differences(one, other, f"{where}[{index}]")
            if len(found) >= MAX_DIFFERENCES:
                return found[:MAX_DIFFERENCES]
        return found
    if recorded == again:
        return []
    shown = [json.dumps(value)[:80] for value in (recorded, again)]
    return [f"{where or 'the record'}: recorded {shown[0]}, re-run {shown[1]}"]
