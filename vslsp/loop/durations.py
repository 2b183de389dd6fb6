"""Planned against executed durations of a trial's steps (issue 41 item 4).

Each skill's planned duration is its reach DMP's ``2τ`` (:func:`vslsp.symbolic.io.durative.skill_durations`),
the duration the learned domain is written with as durative actions; each executed step's
duration is the hand trajectory's time in the simulator (240 Hz physics steps, from the first
waypoint to the last). The learned domain with these durations is what a temporal planner (or
PlanSys2) takes.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from vslsp.outputs import write_text
from vslsp.symbolic.io.durative import durative_domain_pddl, skill_durations

DURATIVE_DOMAIN, DURATIONS = "durative-domain.pddl", "durations.json"


def step_durations(trial: Any, planned: dict[str, float]) -> list[dict]:
    """One record per executed plan step: action, object, planned and executed seconds."""
    records = []
    for run in trial.executions:
        for step in run.steps:
            executed = float(step.trajectory.t[-1]) if step.trajectory is not None and len(step.trajectory.t) else None
            records.append(
                {
                    "action": step.action,
                    "object": step.obj,
                    "planned_s": round(planned.get(step.action, 0.0), 3),
                    "executed_s": round(executed, 3) if executed is not None else None,
                }
            )
    return records


def write_durations(folder: str | Path, trial: Any, library: Any) -> list[str]:
    """Write DURATIVE_DOMAIN (the learned domain, durative) and DURATIONS (the comparison) into
    ``folder``; the lines that tell the comparison."""
    planned = skill_durations(library)
    folder = Path(folder)
    write_text(folder / DURATIVE_DOMAIN, durative_domain_pddl(trial.domain, planned))
    steps = step_durations(trial, planned)
    makespan = sum(s["planned_s"] for s in steps)
    executed = sum(s["executed_s"] or 0.0 for s in steps)
    report = {
        "durations_s": {k: round(v, 3) for k, v in planned.items()},
        "steps": steps,
        "planned_makespan_s": round(makespan, 3),
        "executed_s": round(executed, 3),
    }
    write_text(folder / DURATIONS, json.dumps(report, indent=2) + "\n")
    lines = [
        f"{s['action']} {s['object']}: planned {s['planned_s']:.2f} s, executed {s['executed_s']} s" for s in steps
    ]
    return [*lines, f"plan's makespan (one arm, in sequence) {makespan:.2f} s, executed {executed:.2f} s"]
