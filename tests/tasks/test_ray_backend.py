"""The Ray backend of the trial runner on a local Ray cluster that these tests start on 127.0.0.1.

The test tasks below are defined here (not registered): the Ray workers import them from this
module, found through the ``PYTHONPATH`` that the backend hands its workers.
"""

from __future__ import annotations

import json
import logging
import os
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from helpers.events import HANG_S, became_true, experiment_program, process_gone, wait_until
from helpers.ray_head import ray_folder
from helpers.records import without_times

from vslsp.errors import InputError
from vslsp.tasks import System, Task, TrialResult, get_task, run_trials
from vslsp.tasks.ray_backend import INSTALL, check_ray, worker_env

ray = pytest.importorskip("ray")

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]


class Draw(Task):
    """Succeeds when the seed's three draws sum below 15; keeps the draws as its artefact."""

    name = "ray-test-draw"
    system = System.VSL
    paper_section = "test"
    keep_first = True

    def run_trial(self, seed: int, keep: bool = False) -> TrialResult:
        values = np.random.default_rng(seed).integers(0, 10, size=3)
        ok = int(values.sum()) < 15
        return TrialResult(
            self.name,
            seed,
            ok,
            None if ok else f"drew {values.tolist()}",
            operations=[{"value": int(v)} for v in values],
            details={"sum": int(values.sum())},
            artefacts=values if keep else None,
        )


class RaisesOnOdd(Task):
    name = "ray-test-raises"
    system = System.VSL
    paper_section = "test"

    def run_trial(self, seed: int, keep: bool = False) -> TrialResult:
        if seed % 2:
            raise ValueError(f"odd seed {seed}")
        return TrialResult(self.name, seed, True)


class DiesOnce(Task):
    """Its worker process dies on the first attempt of each trial (a marker file says which)."""

    name = "ray-test-dies-once"
    system = System.VSL
    paper_section = "test"

    def run_trial(self, seed: int, keep: bool = False) -> TrialResult:
        marker = Path(self.settings["folder"]) / f"{seed}.attempted"
        if not marker.exists():
            marker.write_text(str(os.getpid()))
            os._exit(1)
        return TrialResult(
            self.name, seed, True, details={"first_pid": int(marker.read_text()), "retry_pid": os.getpid()}
        )


class AlwaysDies(Task):
    name = "ray-test-always-dies"
    system = System.VSL
    paper_section = "test"

    def run_trial(self, seed: int, keep: bool = False) -> TrialResult:
        os._exit(3)


class Slow(Task):
    """Seed 0 returns once seed 1's trial has started; the others write '<seed>.started' (holding
    their worker's process id), then wait for a 'release' file that the tests never write, then
    write '<seed>.finished': only a trial left running could ever finish."""

    name = "ray-test-slow"
    system = System.VSL
    paper_section = "test"

    def run_trial(self, seed: int, keep: bool = False) -> TrialResult:
        folder = Path(self.settings["folder"])
        awaited = folder / ("1.started" if seed == 0 else "release")
        if seed:
            (folder / f"{seed}.started").write_text(str(os.getpid()))
        became_true(awaited.exists)
        if seed:
            (folder / f"{seed}.finished").write_text("")
        return TrialResult(self.name, seed, True)


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    """A local Ray cluster of 2 CPUs for this module; the backend runs on it (the process is
    connected). HOME is a temporary folder while it runs (Ray writes ~/.ray/auth_token for a new
    local cluster), so are Ray's session files, and the environment, which ``ray.init``
    changes, is restored after."""
    saved = dict(os.environ)
    os.environ["PYTHONPATH"] = os.pathsep.join(
        [str(HERE), str(HERE.parent), str(ROOT)] + ([saved["PYTHONPATH"]] if "PYTHONPATH" in saved else [])
    )
    os.environ["HOME"] = str(tmp_path_factory.mktemp("home"))
    with ray_folder() as folder:
        os.environ["RAY_TMPDIR"] = str(folder)
        ray.init(
            address="local",
            num_cpus=2,
            _node_ip_address="127.0.0.1",
            include_dashboard=False,
            log_to_driver=False,
            logging_level=logging.ERROR,
        )
        try:
            yield ray.get_runtime_context().gcs_address
        finally:
            ray.shutdown()
            os.environ.clear()
            os.environ.update(saved)


def records(results: list[TrialResult]) -> list[dict]:
    """The JSON records of the trials, times excepted."""
    return [without_times(r.to_dict()) for r in results]


def test_ray_gives_the_local_results_in_seed_order(cluster):
    seeds = list(range(10, 18))
    order: list[int] = []
    local = run_trials(Draw(), seeds)
    on_ray = run_trials(Draw(), seeds, workers=2, backend="ray", on_done=lambda r: order.append(r.seed))
    assert sorted(order) == seeds  # progress: each seed reported once, in any order
    assert [r.seed for r in on_ray.results] == seeds and not on_ray.partial and on_ray.interrupted is None
    assert records(on_ray.results) == records(local.results)
    assert {r.success for r in on_ray.results} == {True, False}  # the draws both pass and fail
    # the first seed keeps its artefacts (they come back from the worker), the others do not
    assert np.array_equal(on_ray.results[0].artefacts, local.results[0].artefacts)
    assert all(r.artefacts is None for r in on_ray.results[1:])


def test_a_raising_trial_is_a_failed_result(cluster):
    run = run_trials(RaisesOnOdd(), [0, 1, 2, 3], workers=2, backend="ray")
    assert [r.success for r in run.results] == [True, False, True, False]
    assert run.results[1].error.startswith("ValueError: odd seed 1 (at test_ray_backend.py:")
    assert records(run.results) == records(run_trials(RaisesOnOdd(), [0, 1, 2, 3]).results)


def test_a_killed_worker_is_retried(cluster, tmp_path):
    run = run_trials(DiesOnce(folder=str(tmp_path)), [5, 6], workers=2, backend="ray")
    assert [r.success for r in run.results] == [True, True]
    for result in run.results:
        assert (tmp_path / f"{result.seed}.attempted").exists()
        assert result.details["retry_pid"] != result.details["first_pid"]  # a fresh worker process ran it


def test_a_worker_that_always_dies_is_recorded_not_lost(cluster):
    run = run_trials(AlwaysDies(), [7], backend="ray")
    assert len(run.results) == 1 and not run.results[0].success
    assert run.results[0].error.startswith("worker died: its process ended during the trial 2 times")


def test_sigterm_cancels_the_outstanding_trials_and_keeps_the_finished(cluster, tmp_path):
    def stop(result: TrialResult) -> None:
        if result.seed == 0:
            os.kill(os.getpid(), signal.SIGTERM)

    run = run_trials(Slow(folder=str(tmp_path)), [0, 1, 2, 3], workers=2, backend="ray", on_done=stop)
    assert run.interrupted == "SIGTERM" and run.partial
    assert [r.seed for r in run.results] == [0]
    # The trial of seed 1 had started; its worker process is ended by the cancel (it would
    # otherwise wait, then write '1.finished').
    worker = int((tmp_path / "1.started").read_text())
    wait_until(lambda: process_gone(worker), f"the worker of seed 1 (process {worker}) to end")
    assert not list(tmp_path.glob("*.finished"))
    assert not (tmp_path / "2.started").exists() and not (tmp_path / "3.started").exists()  # never submitted


def test_worker_env_passes_pythonpath_only_when_set(monkeypatch):
    monkeypatch.delenv("PYTHONPATH", raising=False)
    assert worker_env() == {"OMP_NUM_THREADS": "1"}
    monkeypatch.setenv("PYTHONPATH", "/somewhere")
    assert worker_env() == {"OMP_NUM_THREADS": "1", "PYTHONPATH": "/somewhere"}


@pytest.mark.parametrize("address", ["nohost", "ray://host", "host:0", "host:70000", "http://host:6379"])
def test_a_malformed_address_is_refused(address):
    with pytest.raises(InputError, match="is not a Ray cluster address"):
        check_ray(address)


def cli(*args: str, home: Path | None = None, code: str = "") -> subprocess.CompletedProcess:
    """``vslsp`` in a fresh interpreter, after ``code`` (e.g. one that makes ``import ray`` fail),
    with HOME in ``home`` (a local Ray instance writes ~/.ray); None: this process's HOME (the
    ``cluster``'s while it runs: its authentication token). Ray's session files go to a
    temporary folder."""
    program = f"import sys\n{code}\nfrom vslsp.cli import main\nmain(sys.argv[1:])"
    with ray_folder() as folder:
        env = {**os.environ, "RAY_TMPDIR": str(folder), **({"HOME": str(home)} if home is not None else {})}
        return subprocess.run(
            [sys.executable, "-c", program, *args], capture_output=True, text=True, timeout=600, env=env
        )


def test_cli_without_ray_says_how_to_install_it(tmp_path):
    out = tmp_path / "report"
    done = cli(
        "experiment",
        "house-roof",
        "--backend",
        "ray",
        "--out",
        str(out),
        home=tmp_path,
        code="sys.modules['ray'] = None",
    )
    assert done.returncode == 2
    assert done.stderr.strip() == f"error: --backend ray needs Ray, which is not installed: {INSTALL}"
    assert not out.exists()  # refused before any work


def test_cli_refuses_an_address_where_no_cluster_answers(tmp_path):
    done = cli(
        "experiment",
        "house-roof",
        "--backend",
        "ray",
        "--address",
        "127.0.0.1:1",
        "--out",
        str(tmp_path),
        home=tmp_path,
    )
    assert done.returncode == 2 and "Traceback" not in done.stderr
    assert "no Ray cluster answers at --address 127.0.0.1:1" in done.stderr


@pytest.mark.slow
def test_house_roof_on_the_cluster_equals_local(cluster, tmp_path):
    seeds = [0, 1]
    local = run_trials(get_task("house-roof"), seeds)
    done = cli(
        "experiment",
        "house-roof",
        "--trials",
        "2",
        "--workers",
        "2",
        "--backend",
        "ray",
        "--address",
        cluster,
        "--out",
        str(tmp_path / "report"),
        "--json",
    )
    assert done.returncode in (0, 1), done.stderr
    data = json.loads(done.stdout)
    on_ray = [without_times(r) for r in data["results"]]
    assert on_ray == records(local.results)
    assert (tmp_path / "report" / "report.md").exists()
    # the cluster runs on after the command ended (that the run disconnects from it is shown in
    # process by test_ray_cluster.py)
    assert records(run_trials(Draw(), [1, 2], workers=2, backend="ray").results) == records(
        run_trials(Draw(), [1, 2]).results
    )


@pytest.mark.slow
def test_cli_starts_a_local_ray_instance_for_the_run(tmp_path):
    done = cli(
        "experiment",
        "house-roof",
        "--trials",
        "2",
        "--seed",
        "3",
        "--workers",
        "2",
        "--backend",
        "ray",
        "--out",
        str(tmp_path / "report"),
        "--json",
        home=tmp_path,
    )
    assert done.returncode in (0, 1), done.stderr
    data = json.loads(done.stdout)
    assert data["trials"] == 2 and [r["seed"] for r in data["results"]] == [3, 4]
    assert json.loads((tmp_path / "report" / "report.json").read_text())["trials"] == 2


@pytest.mark.slow
def test_ctrl_c_on_the_command_line_cancels_and_writes_the_partial_report(tmp_path):
    with ray_folder() as folder:  # Ray's session files
        _ctrl_c_cancels_and_writes_the_partial_report(tmp_path, folder)


def _ctrl_c_cancels_and_writes_the_partial_report(tmp_path: Path, ray_tmp: Path) -> None:
    markers, out = tmp_path / "markers", tmp_path / "report"
    markers.mkdir()
    # A real Ctrl-C: SIGINT to the command's process group, once seed 0's result is in the driver.
    program = experiment_program("import example_tasks")  # registers ray-test-waits
    env = {
        **os.environ,
        "HOME": str(tmp_path),
        "RAY_TMPDIR": str(ray_tmp),
        "VSLSP_TEST_MARKERS": str(markers),
        "PYTHONPATH": os.pathsep.join([str(HERE), str(HERE.parent), str(ROOT)] + [os.environ.get("PYTHONPATH", "")]),
    }
    command = subprocess.Popen(
        [
            sys.executable,
            "-c",
            program,
            "experiment",
            "ray-test-waits",
            "--trials",
            "4",
            "--workers",
            "2",
            "--backend",
            "ray",
            "--out",
            str(out),
        ],
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    try:
        wait_until(
            lambda: (markers / "0.reported").exists() or command.poll() is not None, "seed 0's result in the driver"
        )
        assert command.poll() is None, command.communicate()[1]
        wait_until(lambda: (markers / "1.started").exists(), "seed 1's trial to start")
        os.killpg(command.pid, signal.SIGINT)
        stdout, stderr = command.communicate(timeout=HANG_S)
    finally:
        if command.poll() is None:
            os.killpg(command.pid, signal.SIGKILL)
    assert command.returncode == 130, stderr  # 128 + SIGINT (docs/bad-input.md)
    assert "SIGINT: stopping now" in stderr
    report = json.loads((out / "report.json").read_text())
    assert report["partial"] and report["interrupted"] == "SIGINT" and report["trials_requested"] == 4
    assert [r["seed"] for r in report["results"]] == [0]
    assert (markers / "1.started").exists() and not list(markers.glob("[123].done"))
