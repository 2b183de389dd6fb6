"""The report folder of a run (vslsp.tasks.report): the failures tallied by cause, the
"Failures" section, links of report.md that resolve, and the shown trial, re-run for its
figures, equal to the trial the run recorded."""

from __future__ import annotations

import json
from collections import Counter

import pytest
from example_tasks import DiceBelowFive
from helpers.records import without_times
from helpers.report import assert_links_resolve

from vslsp.tasks import Run, get_task, run_trials, write_report
from vslsp.tasks.trial import run_one

SEEDS = range(0, 12)  # the die shows 5 or 6 on some of these seeds, less on the others


def record(result) -> dict:
    return without_times(result.to_dict())


def test_failures_are_tallied_by_cause_and_listed_in_their_section(tmp_path):
    task = DiceBelowFive()
    run = run_trials(task, SEEDS)
    failed = [r for r in run.results if not r.success]
    assert failed and len(failed) < len(run.results)  # both kinds on these seeds
    data = write_report(tmp_path, task, run)
    assert data["failure_causes"] == dict(Counter(r.cause for r in failed))
    assert sum(data["failure_causes"].values()) == len(failed) == data["trials"] - data["successes"]
    assert {f["seed"] for f in data["failures"]} == {r.seed for r in failed}
    assert json.loads((tmp_path / "report.json").read_text())["failure_causes"] == data["failure_causes"]
    lines = (tmp_path / "report.md").read_text().splitlines()
    section = lines[lines.index("## Failures") + 2 :]
    listed = section[: next(i for i, line in enumerate(section) if not line.startswith("- seed"))]
    assert listed == [f"- seed {r.seed}: {r.error}" for r in failed]
    for cause, n in data["failure_causes"].items():  # the summary table names each cause with its count
        assert f"{cause}: {n}" in lines[lines.index("|---|---|---|---|---|") + 1]


def test_a_run_without_failures_has_no_failures_section(tmp_path):
    task = DiceBelowFive()
    run = run_trials(task, [r.seed for r in run_trials(task, SEEDS).results if r.success])
    data = write_report(tmp_path, task, run)
    assert data["failure_causes"] == {} and data["failures"] == []
    text = (tmp_path / "report.md").read_text()
    assert "## Failures" not in text and "| none |" in text


def test_every_link_of_report_md_resolves_and_shows_the_chosen_trial(tmp_path):
    task = DiceBelowFive()
    run = run_trials(task, SEEDS)
    data = write_report(tmp_path, task, run)
    shown = data["shown_trial"]
    assert shown["seed"] == task.shown_seed(run.results) and not shown["success"]  # the first failed trial
    assert assert_links_resolve(tmp_path) == [shown["roll"]]


def test_a_partial_run_writes_no_figures_and_says_so(tmp_path):
    task = DiceBelowFive()
    finished = run_trials(task, [0, 1]).results
    data = write_report(tmp_path, task, Run(finished, [0, 1, 2, 3], "SIGINT"))
    assert data["partial"] and data["trials_requested"] == 4 and "shown_trial" not in data
    text = (tmp_path / "report.md").read_text()
    assert "**Partial run**: interrupted (SIGINT) after 2 of 4 trials" in text
    assert assert_links_resolve(tmp_path) == []


@pytest.mark.slow
@pytest.mark.parametrize(("name", "seed"), [("house-roof", 21), ("keep-all-near", 1)])
def test_the_trial_re_run_for_the_figures_equals_the_recorded_one(tmp_path, name, seed):
    # The report re-runs the shown trial with its artefacts kept (the run kept none): it must be
    # the same trial, or the pictures would show another one than the table.
    task = get_task(name)
    recorded = run_one(task, seed, keep=False)
    assert recorded.artefacts is None
    data = write_report(tmp_path, task, Run([recorded], [seed]))
    again = run_one(task, seed, keep=True)
    assert again.artefacts is not None and record(again) == record(recorded)
    assert data["shown_trial"]["seed"] == seed and data["shown_trial"]["success"] == recorded.success
    assert len(assert_links_resolve(tmp_path)) >= 2


def test_a_report_says_where_it_came_from_and_when_its_rate_says_little(tmp_path):
    import platform
    import subprocess
    from pathlib import Path

    import vslsp

    task = DiceBelowFive()
    data = write_report(tmp_path, task, run_trials(task, range(3)))
    made = data["provenance"]
    assert made["python"] == platform.python_version() and made["platform"] == platform.platform()
    assert made["vslsp"] and made["command"]
    checkout = Path(vslsp.__file__).resolve().parents[1]
    if (checkout / ".git").exists():
        head = subprocess.run(["git", "-C", str(checkout), "rev-parse", "HEAD"], capture_output=True, text=True)
        assert made["commit"] == head.stdout.strip()
    text = (tmp_path / "report.md").read_text()
    assert made["seeds"] == [0, 2]
    assert "with 3 trials the rate says little" in text and f"Made by vslsp {made['vslsp']}" in text
    lo, hi = data["success_ci95"]
    assert f"spans {100 * lo:.0f}-{100 * hi:.0f} %" in text
    many = write_report(tmp_path / "many", task, run_trials(task, range(400)))
    assert many["success_ci95"][1] - many["success_ci95"][0] < 0.2
    assert "says little" not in (tmp_path / "many" / "report.md").read_text()
