"""``vslsp experiment --tasks FILE.py NAME``: a user's own tasks file, run in two worker processes
(and on Ray), its mistakes refused before any work; a runner script without a main guard
refused in the parent, naming its line, instead of being run again by every worker."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from helpers.cli import REPO, vslsp_process

TASKS = textwrap.dedent("""
    import numpy as np

    from vslsp.tasks import System, Task, TrialResult, register


    @register
    class CoinHeads(Task):
        name = "coin-heads"
        system = System.VSL
        paper_section = "a user's task"
        description = "Tosses a coin from the seed; succeeds on heads."

        def run_trial(self, seed: int, keep: bool = False) -> TrialResult:
            heads = bool(np.random.default_rng(seed).integers(0, 2))
            return TrialResult(self.name, seed, heads, None if heads else "tails", details={"pid": 0, "heads": heads})
""")

SEEDS_HEADS = {0: True, 1: False, 2: True, 3: True}  # numpy's default_rng(seed).integers(0, 2)


@pytest.fixture
def tasks_file(tmp_path: Path) -> Path:
    path = tmp_path / "my_tasks.py"
    path.write_text(TASKS)
    return path


def run(tmp_path: Path, *args: object) -> tuple[subprocess.CompletedProcess[str], dict]:
    done = vslsp_process("experiment", *args, "--json", cwd=tmp_path)
    return done, json.loads(done.stdout)


def test_a_tasks_file_runs_in_two_workers_as_in_one(tasks_file, tmp_path):
    common = ("--tasks", tasks_file, "coin-heads", "--trials", "4")
    two, data = run(tmp_path, *common, "--workers", "2", "--out", tmp_path / "two")
    assert two.returncode == 1, two.stderr  # seed 1 is tails: a failed trial
    assert {r["seed"]: r["success"] for r in data["results"]} == SEEDS_HEADS
    assert data["failures"] == [{"seed": 1, "error": "tails"}] and "Traceback" not in two.stderr
    one, alone = run(tmp_path, *common, "--out", tmp_path / "one")
    assert [r["success"] for r in alone["results"]] == [r["success"] for r in data["results"]]
    assert (tmp_path / "two" / "report.md").is_file()
    listed, entries = run(tmp_path, "--tasks", tasks_file, "--list")
    assert "coin-heads" in [e["name"] for e in entries["experiments"]]


@pytest.mark.parametrize(
    "body, message",
    [
        ("def broken(:\n", "cannot load tasks file my_tasks.py, line 1: SyntaxError"),
        ("x = 1\nraise RuntimeError('no robot here')\n", "my_tasks.py, line 2: RuntimeError: no robot here"),
        ("x = 1\n", "tasks file my_tasks.py registers no task; decorate a Task subclass with @register"),
        ("import sys\nsys.exit(3)\n", "cannot load tasks file my_tasks.py, line 2: SystemExit"),
    ],
)
def test_a_broken_tasks_file_is_refused_before_any_work(tmp_path, body, message):
    (tmp_path / "my_tasks.py").write_text(body)
    done, data = run(tmp_path, "--tasks", "my_tasks.py", "coin-heads", "--out", tmp_path / "out")
    assert done.returncode == 2 and message in data["error"], done.stderr
    assert "Traceback" not in done.stderr and not (tmp_path / "out").exists()


@pytest.mark.parametrize("name, message", [("notes.txt", "must be a Python file"), ("gone.py", "no such file")])
def test_a_tasks_file_that_is_not_one_is_refused(tmp_path, name, message):
    (tmp_path / "notes.txt").write_text("x")
    done, data = run(tmp_path, "--tasks", name, "coin-heads")
    assert done.returncode == 2 and message in data["error"]


def script(tmp_path: Path, guarded: bool) -> subprocess.CompletedProcess[str]:
    """A user's runner script calling vslsp's command with two workers, with or without the guard."""
    args = ["experiment", "--tasks", "my_tasks.py", "coin-heads", "--trials", "4", "--workers", "2"]
    call = f"main({args + ['--out', str(tmp_path / 'out')]!r})"
    body = "from vslsp.cli import main\n\n" + (f'if __name__ == "__main__":\n    {call}\n' if guarded else call + "\n")
    (tmp_path / "runner.py").write_text(body)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(REPO), os.environ.get("PYTHONPATH", "")])}
    return subprocess.run(
        [sys.executable, "runner.py"], cwd=tmp_path, env=env, capture_output=True, text=True, timeout=600
    )


def test_a_runner_script_without_a_main_guard_is_refused_naming_its_line(tasks_file, tmp_path):
    done = script(tmp_path, guarded=False)
    assert done.returncode == 2
    assert done.stderr.count("error:") == 1 and "runner.py, line 3: trials in 2 worker processes" in done.stderr
    assert 'put the call under `if __name__ == "__main__":`' in done.stderr
    assert "in use by another vslsp run" not in done.stderr and not (tmp_path / "out").exists()
    guarded = script(tmp_path, guarded=True)
    assert guarded.returncode == 1 and "coin-heads: 3/4 trials succeeded" in guarded.stdout, guarded.stderr


@pytest.mark.slow
def test_a_tasks_file_reaches_ray_workers_by_value(tasks_file, tmp_path):
    pytest.importorskip("ray")
    from helpers.ray_head import ray_folder

    with ray_folder() as folder:
        env = {**os.environ, "RAY_TMPDIR": str(folder), "HOME": str(tmp_path)}
        done = subprocess.run(
            [sys.executable, "-m", "vslsp", "experiment", "--tasks", str(tasks_file), "coin-heads", "--trials", "4"]
            + ["--workers", "2", "--backend", "ray", "--json", "--out", str(tmp_path / "ray")],
            cwd=tmp_path,
            env={**env, "PYTHONPATH": os.pathsep.join([str(REPO), os.environ.get("PYTHONPATH", "")])},
            capture_output=True,
            text=True,
            timeout=600,
        )
    assert done.returncode == 1, done.stderr
    assert {r["seed"]: r["success"] for r in json.loads(done.stdout)["results"]} == SEEDS_HEADS
