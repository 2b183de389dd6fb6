"""``vslsp studio --tasks FILE.py``: a user's tasks (chosen on the command line, never by a request)
are offered by the API and run by the studio's jobs, which load the same file; a file that does not
load is exit 2 before anything is served."""

from __future__ import annotations

import subprocess
import sys
import textwrap

import pytest
from helpers.events import wait_until
from helpers.studio import client

from vslsp.tasks import load_task_files
from vslsp.tasks.task_files import ENV

TASKS = textwrap.dedent("""
    from vslsp.tasks import System, Task, TrialResult, register


    @register
    class EvenSeed(Task):
        name = "even-seed"
        system = System.VSL
        paper_section = "a user's task in the studio"
        description = "Succeeds on even seeds."

        def run_trial(self, seed: int, keep: bool = False) -> TrialResult:
            return TrialResult(self.name, seed, seed % 2 == 0, None if seed % 2 == 0 else "odd seed")
""")


def test_a_tasks_file_given_to_the_studio_is_offered_and_run(studio_root, tmp_path, monkeypatch):
    path = tmp_path / "even_tasks.py"
    path.write_text(TASKS)
    monkeypatch.setenv(ENV, "")  # restored afterwards: no later test's process loads this file
    load_task_files([path])  # what `vslsp studio --tasks` does before it serves
    web = client(studio_root)
    assert "even-seed" in [e["name"] for e in web.get("/api/experiments").json()["experiments"]]
    run_id = web.post("/api/runs", json={"experiment": "even-seed", "trials": 4, "seed": 10}).json()["id"]
    ended = ("done", "failed", "cancelled")
    wait_until(lambda: web.get(f"/api/runs/{run_id}").json()["state"] in ended, f"the run {run_id} to end")
    status = web.get(f"/api/runs/{run_id}").json()
    assert (status["done"], status["successes"]) == (4, 2), status  # run by the job's own process


@pytest.mark.parametrize("body, message", [("x = 1\n", "registers no task"), ("def f(:\n", "SyntaxError")])
def test_a_tasks_file_that_does_not_load_stops_the_studio_before_it_serves(tmp_path, body, message):
    (tmp_path / "bad.py").write_text(body)
    done = subprocess.run(
        [sys.executable, "-m", "vslsp", "studio", "--no-browser", "--root", str(tmp_path)]
        + ["--tasks", str(tmp_path / "bad.py")],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 2 and message in done.stderr and "Traceback" not in done.stderr
