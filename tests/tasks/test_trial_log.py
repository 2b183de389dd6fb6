"""A long run's trials as JSON lines (vslsp.tasks.trial_log): each round's trials are appended
as they finish, a second run with the same file runs only the trials it lacks, and a run
stopped early keeps what finished."""

from __future__ import annotations

import json

import example_tasks  # noqa: F401  (registers dice-below-five)

from vslsp.tasks import get_task, run_trials, trial_log


def dice(group: dict, seeds: list[int], ran: list[int]) -> tuple[list[dict], bool]:
    ran.extend(seeds)
    results = run_trials(get_task(group["experiment"]), seeds).results
    return trial_log.trial_records(results, **group), False


def test_a_second_run_runs_only_the_trials_the_file_lacks(tmp_path):
    path, groups, ran = tmp_path / "trials.jsonl", [{"experiment": "dice-below-five", "pass": 1}], []
    records = trial_log.read(path)
    assert records == []
    trial_log.run_rounds(records, groups, list(range(6)), 4, lambda g, s: dice(g, s, ran), path)
    assert ran == list(range(6))  # two rounds: 0-3, 4-5
    kept = [json.loads(line) for line in path.read_text().splitlines()]
    assert [r["seed"] for r in kept] == list(range(6)) and all(r["pass"] == 1 for r in kept)
    again = trial_log.read(path)
    trial_log.run_rounds(again, groups, list(range(10)), 4, lambda g, s: dice(g, s, ran), path)
    assert ran[6:] == [6, 7, 8, 9]  # only the missing seeds
    row = trial_log.success_row(trial_log.of(again, groups[0]))
    assert row["trials"] == 10 and row["successes"] + len(row["failed"]) == 10
    expected = sum(get_task("dice-below-five").run_trial(s).success for s in range(10))
    assert row["successes"] == expected
    assert 0.0 <= row["interval_95"][0] <= row["rate"] <= row["interval_95"][1] <= 1.0


def test_a_stopped_round_ends_the_run_and_keeps_what_finished(tmp_path):
    path, ran = tmp_path / "trials.jsonl", []

    def stops(group: dict, seeds: list[int]) -> tuple[list[dict], bool]:
        records, _ = dice(group, seeds[:1], ran)
        return records, True  # Ctrl-C after the first trial

    groups = [{"experiment": "dice-below-five", "pass": k} for k in (1, 2)]
    trial_log.run_rounds([], groups, list(range(4)), 4, stops, path)
    assert ran == [0] and len(trial_log.read(path)) == 1
