"""One job of the studio, in its own process (``python -m vslsp.studio.worker STATUS``): it outlives
the page that started it. It reads its request from the status file. An experiment run (the default
``kind``) runs the trials with :func:`vslsp.tasks.run_trials` and writes progress to the status file
after each trial (``state``, ``done``, ``total``, ``successes``), then the report; a ``figures`` job
re-runs one trial of a report and draws its pictures (:mod:`vslsp.studio.trial_figures`). The studio's root
is the status file's ``root`` (the job runs from a working folder of its own, never the root). Its trials'
cameras publish their newest view to the file the studio named in the environment (:mod:`vslsp.sim.live`)."""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path
from typing import Any


def main(status_path: str) -> int:
    """Do the job in ``status_path``; 0 when it is done, 1 when it failed."""
    import signal

    from vslsp.errors import Interrupted, VslspError
    from vslsp.studio.runs import write_status

    def cancelled(number: int, _frame: object) -> None:
        raise Interrupted(signal.Signals(number).name)

    path = Path(status_path)
    status = json.loads(path.read_text())
    # The studio cancels a job with SIGTERM. Until here its default action ends the process (the
    # studio's cancel mark then says cancelled); from here on every line is inside the ``try``, so a
    # cancel at any moment ends with a status written.
    signal.signal(signal.SIGTERM, cancelled)
    try:
        status["pid"] = os.getpid()  # a later studio tells a live job from a dead one by it
        write_status(path, status)
        if status.get("kind") == "figures":
            from vslsp.studio.trial_figures import draw

            status.update(draw(Path(status["root"]), status["request"]), state="done")
        else:
            run(path, status)
    except (Interrupted, KeyboardInterrupt):
        status.update(state="cancelled", error="cancelled before any trial finished")
    except VslspError as error:
        status.update(state="failed", error=str(error))
    except Exception as error:  # a trial's own failure is in its record; this is the job itself failing
        status.update(state="failed", error=f"internal error ({type(error).__name__}: {error})")
    write_status(path, status)
    return 0 if status["state"] == "done" else 1


def run(path: Path, status: dict[str, Any]) -> None:
    """The experiment run of ``status["request"]``: its trials, then the report in ``report/``."""
    from vslsp.studio.runs import task_options, write_status
    from vslsp.tasks import get_task, run_trials, write_report

    request = status["request"]
    task = get_task(request["experiment"], **task_options(request, str(path.parent / "report")))
    seeds = list(range(request["seed"], request["seed"] + request["trials"]))

    def done(result: Any) -> None:
        status["done"] += 1
        status["successes"] += int(result.success)
        write_status(path, status)

    outcome = run_trials(task, seeds, workers=request["workers"], backend=request["backend"], on_done=done)
    status["state"] = "writing report"
    write_status(path, status)
    if outcome.results:
        write_report(path.parent / "report", task, outcome)
        status["report"] = f"{status['folder']}/report"
    if outcome.interrupted:  # cancelled (SIGTERM from the studio): the finished trials are in the report
        status.update(state="cancelled", error=f"cancelled after {len(outcome.results)} of {len(seeds)} trials")
    else:
        status["state"] = "done"


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
