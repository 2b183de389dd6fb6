"""What the reports pages and ``GET /api/reports/...`` show of a report folder (as ``vslsp experiment
--out`` writes it, :mod:`vslsp.tasks.report`): the folder's files by kind, one trial's record with its
pictures in the order the report drew them, its plan and replans, its video and VSL-3D's clouds.

A report draws its figures (and, for VSL-3D, saves its clouds) for one trial, ``shown_trial`` of
``report.json``; every other trial has its record and, with ``--video``, its video, until the studio
draws its pictures (:mod:`vslsp.studio.trial_figures`) into ``trials/SEED/`` of the report folder, listed
in ``trials/SEED/figures.json`` as ``shown_trial`` lists the report's.
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

from vslsp.errors import InputError
from vslsp.studio.files import Missing, inside, relative

#: ``REL/trials/SEED``: one trial of the report folder REL.
TRIAL = re.compile(r"^(?P<folder>.+?)/trials/(?P<seed>[0-9]{1,10})/?$")
_KINDS = {".png": "images", ".jpg": "images", ".mp4": "videos", ".webm": "videos", ".ply": "clouds"}
_KINDS.update({".npz": "clouds", ".pddl": "plans", ".plan": "plans", ".txt": "plans"})
#: The pictures the studio drew for one trial, relative to the report folder (``figures.json`` lists them).
TRIAL_FOLDER = "trials/{seed}"
DRAWN = "figures.json"


def report_folders(root: Path) -> list[str]:
    """The report folders under the root (folders with a ``report.json``), relative to it."""
    from vslsp.studio.files import listing

    found = listing(root, (".json",))
    return [p.rsplit("/", 1)[0] if "/" in p else "." for p in found if p.rsplit("/", 1)[-1] == "report.json"]


def split_trial(rel: str) -> tuple[str, int] | None:
    """``(folder, seed)`` when ``rel`` names a trial (``FOLDER/trials/SEED``) and not a report folder."""
    found = TRIAL.match(rel)
    return (found["folder"], int(found["seed"])) if found else None


def trial_of(root: Path, rel: str) -> tuple[str, int] | None:
    """``(folder, seed)`` when ``rel`` is ``FOLDER/trials/SEED`` and not itself a report folder."""
    trial = split_trial(rel)
    if trial is None or (inside(root, rel, must_exist=False) / "report.json").is_file():
        return None
    return trial


def read_summary(root: Path, rel: str) -> tuple[Path, dict]:
    """The report folder ``rel`` (resolved) and its report.json."""
    folder = inside(root, rel)
    summary_file = folder / "report.json"
    if not summary_file.is_file():
        raise Missing(f"{rel}: not a report folder (no report.json)")
    try:
        summary = json.loads(summary_file.read_text())
    except (ValueError, UnicodeDecodeError):
        raise InputError(f"{rel}/report.json: not JSON") from None
    if not isinstance(summary, dict):
        raise InputError(f"{rel}/report.json: not a report (a JSON object)")
    return folder, summary


def read_report(root: Path, rel: str) -> dict:
    """A report folder: ``summary`` (report.json), ``markdown`` (report.md), ``images`` (in order),
    ``videos``, ``clouds`` (.ply/.npz), ``plans`` (.pddl/.plan/.txt), ``trials`` (each trial's
    ``seed``, ``success``, ``error`` and page ``link``), paths relative to the root."""
    folder, summary = read_summary(root, rel)
    markdown = (folder / "report.md").read_text() if (folder / "report.md").is_file() else ""
    found: dict[str, list[str]] = {"images": [], "videos": [], "clouds": [], "plans": []}
    base = root.resolve()
    for path in sorted(folder.rglob("*")):
        kind = _KINDS.get(path.suffix.lower())
        inner = path.relative_to(folder).parts
        if len(inner) > 2 and inner[0] == "trials" and inner[1].isdigit():
            continue  # a trial's pictures drawn by the studio: on its own page
        if kind and path.is_file() and path.resolve().is_relative_to(base):
            found[kind].append(relative(root, path))
    name = relative(root, folder)
    shown = summary["shown_trial"].get("seed") if isinstance(summary.get("shown_trial"), dict) else None
    trials = [
        {
            "seed": record.get("seed"),
            "success": record.get("success"),
            "error": record.get("error"),
            "link": f"/reports/{name}/trials/{record.get('seed')}",
            "pictures": record.get("seed") == shown or drawn_figures(root, folder, record["seed"]) is not None,
        }
        for record in summary.get("results") or []
        if isinstance(record, dict) and isinstance(record.get("seed"), int)
    ]
    return {"folder": name, "summary": summary, "markdown": markdown, **found, "trials": trials}


def read_trial(root: Path, rel: str, seed: int) -> dict:
    """One trial of the report folder ``rel``: ``record`` (its entry of ``results``), ``shown`` (the
    report drew its figures), ``pictures`` (``"report"``, ``"studio"`` when the studio drew them, with
    ``check``: ``{"matches", "differences"}`` of the re-run's record, or None), ``images``
    (``[{"file", "title", "caption"}]`` in the report's order),
    ``plans`` (``[{"title", "plan": [step, ...]}]``: the first plan and each replan), ``files`` (its
    domain, problem and plan files), ``video``, ``clouds`` and ``trajectories`` (paths relative to the
    root; a file the report names but that is not there is left out)."""
    folder, summary = read_summary(root, rel)
    record = next(
        (r for r in summary.get("results") or [] if isinstance(r, dict) and r.get("seed") == seed),
        None,
    )
    if record is None:
        raise Missing(f"{rel}: no trial with seed {seed} in its report.json")
    shown: dict = summary["shown_trial"] if isinstance(summary.get("shown_trial"), dict) else {}
    is_shown = shown.get("seed") == seed
    drawn, base, check = shown if is_shown else {}, relative(root, folder), None
    studio = None if is_shown else drawn_figures(root, folder, seed)
    if studio is not None:
        drawn, base = studio, f"{base}/{TRIAL_FOLDER.format(seed=seed)}"
        check = {"matches": bool(studio.get("matches")), "differences": list(studio.get("differences") or [])}

    def under(value: Any, base: str = base) -> str | None:
        if not isinstance(value, str) or not value:
            return None
        try:
            path = inside(root, f"{base}/{value}")
        except InputError:
            return None
        return relative(root, path) if path.is_file() else None

    images: list[dict] = []
    files: list[dict] = []
    for key, value in drawn.items():
        if key == "images" and isinstance(value, list):  # VSL-SP: each observed pair with its caption
            for image in value:
                path = under(image.get("file")) if isinstance(image, dict) else None
                if path:
                    images.append({"file": path, "title": str(image.get("title")), "caption": image.get("caption")})
        elif (path := under(value)) and path.lower().endswith((".png", ".jpg")):
            images.append({"file": path, "title": key.replace("_", " "), "caption": None})
        elif path and path.endswith((".pddl", ".plan", ".txt")):
            files.append({"title": key, "file": path})
    report_folder = relative(root, folder)
    video = under(record.get("video"), report_folder) or under(f"videos/trial-{seed}.mp4", report_folder)
    clouds = [path for path in (under(c) for c in drawn.get("clouds") or []) if path]
    trajectories = next((i["file"] for i in images if i["title"] in ("trajectories", "trajectory")), None)
    return {
        "folder": relative(root, folder),
        "seed": seed,
        "record": record,
        "shown": is_shown,
        "shown_seed": shown.get("seed"),
        "pictures": "report" if is_shown else "studio" if studio is not None else None,
        "check": check,
        "images": images,
        "plans": plans_of(drawn) or plans_of(record),
        "files": files,
        "video": video,
        "clouds": clouds,
        "trajectories": trajectories,
    }


def drawn_figures(root: Path, folder: Path, seed: int) -> dict | None:
    """``trials/SEED/figures.json`` of the report ``folder``: the pictures the studio drew for trial ``seed``
    (paths relative to ``trials/SEED/``), or None when it drew none (or the file leaves the root)."""
    try:
        path = inside(root, f"{relative(root, folder)}/{TRIAL_FOLDER.format(seed=seed)}/{DRAWN}")
        data = json.loads(path.read_text())
    except (InputError, OSError, ValueError, UnicodeDecodeError):
        return None
    return data if isinstance(data, dict) else None


def plans_of(data: dict) -> list[dict]:
    """The plans of a trial's record or figures, in order: each execution's first plan, then its
    replans (VSL-SP's execution monitor replans when a step's effect is missing), and the empty plan
    that confirms the goal holds once a plan has run ("goal check")."""
    executions = data.get("executions")
    if not isinstance(executions, list):
        executions = [data] if isinstance(data.get("plans"), list) else []
    found = []
    for number, execution in enumerate(executions, start=1):
        plans = execution.get("plans") if isinstance(execution, dict) else None
        replans = 0
        for index, plan in enumerate(plans or []):
            if isinstance(plan, dict) and isinstance(plan.get("plan"), list):
                if index > 0 and plan["plan"]:
                    replans += 1
                title = "plan" if index == 0 else f"replan {replans}" if plan["plan"] else "goal check"
                if len(executions) > 1:
                    title = f"execution {number}: {title}"
                found.append({"title": title, "plan": [str(step) for step in plan["plan"]]})
    return found
