"""The task framework: the registry, the one trial runner (seed order, workers, a raising trial,
a dying worker, interrupts) and the one report layout, on tasks registered as a user would."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest
from example_tasks import DiceBelowFive, Troublesome
from helpers.cli import vslsp
from helpers.events import HANG_S, experiment_program, process_gone, wait_until
from helpers.paper_experiments import PAPER
from helpers.records import without_times

from vslsp.errors import InputError
from vslsp.tasks import Run, get_task, list_tasks, run_trials, write_report

HERE = Path(__file__).parent


def test_every_experiment_of_the_paper_is_registered_with_its_system(capsys):
    code, out, _ = vslsp(capsys, "experiment", "--list", "--json")
    assert code == 0
    listed = json.loads(out)["experiments"]
    names = [entry["name"] for entry in listed]
    assert set(PAPER) <= set(names)
    systems = {entry["name"]: entry["system"] for entry in listed}
    assert systems["house-roof"] == "VSL" and systems["table-cleaning"] == "VSL-3D"
    assert systems["pull-in-order"] == "VSL-SP" and all(entry["paper_section"] for entry in listed)
    assert DiceBelowFive in list_tasks()


def test_a_user_task_runs_through_the_command_with_the_common_report(tmp_path, capsys):
    code, out, _ = vslsp(
        capsys, "experiment", "dice-below-five", "--trials", "6", "--seed", "3", "--json", "--out", tmp_path
    )
    data = json.loads(out)
    rolls = [r["roll"] for r in data["results"]]
    assert [r["seed"] for r in data["results"]] == list(range(3, 9))
    assert data["successes"] == sum(roll < 5 for roll in rolls) and data["trials"] == 6
    assert code == (0 if data["successes"] == 6 else 1)
    for key in ("experiment", "trials", "successes", "success_rate", "mean_time_s", "failures", "results", "report"):
        assert key in data
    assert data["mean_roll"] == pytest.approx(sum(rolls) / 6)
    assert json.loads((tmp_path / "report.json").read_text())["results"] == data["results"]
    report = (tmp_path / "report.md").read_text()
    assert report.splitlines()[0].startswith("# dice-below-five") and "| 6 (seeds 3-8) |" in report
    assert (tmp_path / data["shown_trial"]["roll"]).stat().st_size > 100


def test_options_a_task_does_not_take_are_refused_before_any_work():
    with pytest.raises(InputError, match="--faults applies to the VSL-SP experiments"):
        get_task("house-roof", faults=True)
    with pytest.raises(InputError, match="--method applies to the VSL-3D experiments"):
        get_task("pull-in-order", method="icp")
    with pytest.raises(InputError, match="unknown experiment"):
        get_task("tidy-the-kitchen")


def test_results_come_in_seed_order_the_same_on_one_or_two_workers():
    task = get_task("dice-below-five")
    one = run_trials(task, range(10, 16), workers=1)
    two = run_trials(task, range(10, 16), workers=2)
    strip = [without_times(r.to_dict()) for r in one.results]
    assert strip == [without_times(r.to_dict()) for r in two.results]
    assert [r.seed for r in two.results] == list(range(10, 16)) and not two.partial


def test_a_raising_trial_is_recorded_and_a_dying_worker_is_replaced(tmp_path, monkeypatch):
    monkeypatch.setenv("VSLSP_TEST_FLAGS", str(tmp_path))
    run = run_trials(Troublesome(), [0, 1, 2, 3], workers=2)
    outcome = {r.seed: r for r in run.results}
    assert sorted(outcome) == [0, 1, 2, 3]
    assert not outcome[1].success and "RuntimeError: the gripper caught fire" in outcome[1].error
    assert outcome[2].success and (tmp_path / "attempt-2").exists()  # died once, retried in a fresh worker
    assert outcome[0].success and outcome[3].success


@pytest.mark.slow
@pytest.mark.parametrize("signal_name", ["SIGTERM", "SIGINT"])
def test_an_interrupt_stops_the_run_ends_the_workers_and_keeps_the_finished_trials(tmp_path, signal_name):
    markers, out = tmp_path / "markers", tmp_path / "report"
    markers.mkdir()
    env = {
        **os.environ,
        "VSLSP_TEST_MARKERS": str(markers),
        "PYTHONPATH": os.pathsep.join([str(HERE), str(HERE.parent), os.environ.get("PYTHONPATH", "")]),
    }
    arguments = ["experiment", "troublesome", "--trials", "40", "--seed", "10", "--workers", "2", "--json"]
    process = subprocess.Popen(
        [sys.executable, "-c", experiment_program("import example_tasks"), *arguments, "--out", str(out)],
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    try:
        wait_until(lambda: any(markers.glob("*.reported")) or process.poll() is not None, "a trial's result")
        if signal_name == "SIGINT":
            os.killpg(process.pid, signal.SIGINT)  # Ctrl-C: the terminal signals the whole process group
        else:
            process.send_signal(signal.SIGTERM)
        stdout, stderr = process.communicate(timeout=HANG_S)
    finally:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)
    # 128 + the signal's number (docs/bad-input.md)
    assert process.returncode == {"SIGINT": 130, "SIGTERM": 143}[signal_name], stderr
    data = json.loads(stdout)
    assert data["partial"] and data["interrupted"] == signal_name and 1 <= data["trials"] < 40  # no drain of all 40
    assert data["trials_requested"] == 40 and f"{signal_name}: stopping now" in stderr
    report = json.loads((out / "report.json").read_text())
    assert [r["seed"] for r in report["results"]] == list(range(10, 10 + data["trials"]))
    assert "Partial run" in (out / "report.md").read_text()
    # every worker that ran a trial has ended with the command
    # (a file may be empty: its worker was ended while writing it)
    workers = {int(text) for running in markers.glob("*.running") if (text := running.read_text())}
    assert workers and os.getpid() not in workers and process.pid not in workers  # trials ran in worker processes
    wait_until(lambda: all(process_gone(pid) for pid in workers), f"the workers {sorted(workers)} to end")


def test_the_report_of_a_run_is_byte_equal_for_the_same_seeds_on_one_or_two_workers(tmp_path):
    task = get_task("dice-below-five")
    for workers in (1, 2):
        run = run_trials(task, range(5), workers=workers)
        for result in run.results:
            result.time_s = result.cpu_s = 0.0
            result.stages_s = None
        write_report(tmp_path / str(workers), task, run)
    assert (tmp_path / "1" / "report.json").read_text().replace("/1", "") == (
        tmp_path / "2" / "report.json"
    ).read_text().replace("/2", "")


def test_a_run_reports_partial_when_not_every_seed_finished():
    run = Run([], [4, 5])
    assert run.partial


@pytest.mark.parametrize(
    "args",
    [
        ["experiment", "tidy-the-kitchen", "--json"],
        ["experiment", "house-roof", "--seed", "-1", "--json"],
        ["experiment", "house-roof", "--faults", "--json"],
    ],
)
def test_json_is_printed_for_bad_input_too(args, capsys):
    code, out, _ = vslsp(capsys, *args)
    data = json.loads(out)
    assert code == 2 and data["exit_code"] == 2 and data["error"]


def test_an_unknown_planner_is_refused_before_any_trial(tmp_path, capsys):
    code, out, _ = vslsp(capsys, "experiment", "pull-in-order", "--planner", "magic", "--json", "--out", tmp_path)
    assert code == 2 and "magic" in json.loads(out)["error"] and not (tmp_path / "report.json").exists()
