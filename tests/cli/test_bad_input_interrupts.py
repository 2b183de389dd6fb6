"""Ctrl-C and SIGTERM at any phase, with any number of workers: the report of the finished
trials is written first, the exit code is 130 / 143 (docs/bad-input.md), and no planner process
or temporary folder is left behind."""

from __future__ import annotations

import json
import signal

import pytest
from helpers.events import became_true, process_gone, wait_until
from helpers.processes import planner_processes, start

SIGNALS = {"SIGINT": (signal.SIGINT, 130), "SIGTERM": (signal.SIGTERM, 143)}


def interrupted(args: list[object], tmp_path, marker: str, number: int) -> tuple[int, str, str]:
    """Run ``vslsp ARGS``, send it signal ``number`` once the test task has written ``marker``
    (in $VSLSP_TEST_MARKERS), and return its exit code, stdout and stderr."""
    process = start(args, tmp_path)
    try:
        assert became_true(lambda: (tmp_path / "markers" / marker).exists(), process)
        process.send_signal(number)
        stdout, stderr = process.communicate(timeout=120)
    finally:
        process.kill()
    return process.returncode, stdout, stderr


@pytest.mark.parametrize("workers", [1, 2])
@pytest.mark.parametrize("name", list(SIGNALS))
def test_an_interrupt_during_the_trials_keeps_the_finished_ones(tmp_path, workers, name):
    number, code = SIGNALS[name]
    out = tmp_path / "report"
    args = ["experiment", "test-waits-after-the-first", "--trials", "4", "--workers", workers, "--json", "--out", out]
    returncode, stdout, stderr = interrupted(args, tmp_path, "waiting-1", number)
    assert returncode == code, stderr
    assert "Traceback" not in stderr and f"{name}: stopping now" in stderr
    summary = json.loads(stdout)
    report = json.loads((out / "report.json").read_text())
    for data in (summary, report):
        assert data["partial"] and data["interrupted"] == name and data["trials_requested"] == 4
        assert [r["seed"] for r in data["results"]] == [0] and data["results"][0]["success"]
    assert "Partial run" in (out / "report.md").read_text()


@pytest.mark.parametrize("name", list(SIGNALS))
def test_a_worker_left_without_work_ends_with_the_run_and_prints_nothing(tmp_path, name):
    """Two trials on two workers: once seed 0 is in the driver its worker waits for work that
    never comes; ended there by the interrupt, it prints no traceback (it printed the pool
    loop's, or the initializer's when it was still starting)."""
    number, code = SIGNALS[name]
    out = tmp_path / "report"
    args = ["experiment", "test-waits-after-the-first", "--trials", "2", "--workers", "2", "--json", "--out", out]
    returncode, stdout, stderr = interrupted(args, tmp_path, "waiting-1", number)
    assert returncode == code, stderr
    assert "Traceback" not in stderr and stderr.startswith(f"{name}: stopping now"), stderr
    assert [r["seed"] for r in json.loads(stdout)["results"]] == [0]


@pytest.mark.parametrize("name", list(SIGNALS))
def test_an_interrupt_while_the_figures_are_drawn_keeps_the_report(tmp_path, name):
    number, code = SIGNALS[name]
    out = tmp_path / "report"
    args = ["experiment", "test-slow-figures", "--trials", "3", "--out", out]
    returncode, _, stderr = interrupted(args, tmp_path, "figures", number)
    assert returncode == code, stderr
    assert "Traceback" not in stderr
    report = json.loads((out / "report.json").read_text())
    assert [r["seed"] for r in report["results"]] == [0, 1, 2] and report["successes"] == 3
    assert report["interrupted"] == name and "shown_trial" not in report
    assert "| 3 (seeds 0-2) | 3 |" in (out / "report.md").read_text()


@pytest.mark.parametrize("workers", [1, 2])
def test_sigterm_ends_the_planner_of_every_worker_and_removes_its_folder(tmp_path, workers):
    out = tmp_path / "report"
    args = ["experiment", "test-plans", "--trials", "2", "--workers", workers, "--out", out]
    process = start(args, tmp_path)
    try:
        assert became_true(lambda: bool(planner_processes(process.pid)), process)
        planners = planner_processes(process.pid)
        assert list((tmp_path / "tmp").glob("vslsp-fd-*"))
        process.send_signal(signal.SIGTERM)
        _, stderr = process.communicate(timeout=120)
    finally:
        process.kill()
    assert process.returncode == 143, stderr
    wait_until(lambda: all(process_gone(pid) for pid in planners), f"the planners {planners} to end")
    assert list((tmp_path / "tmp").glob("vslsp-*")) == []
    assert json.loads((out / "report.json").read_text())["interrupted"] == "SIGTERM"
