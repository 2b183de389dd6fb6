"""A long run's trials kept as JSON lines, one trial a line (``benchmarks/bench_slips.py``,
``benchmarks/bench_views.py``): a run stopped early (Ctrl-C, SIGTERM, the end of a session)
loses no finished trial, and a later run with the same file runs only the trials it lacks, so
that hundreds of trials may be gathered over several runs or machines.

The trials run in rounds of seeds, each round every group (an experiment with its options), so
that a run stopped early still compares the groups on the same seeds. A trial's line holds its
group's fields, its seed, success, CPU seconds, cause and error.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections import Counter
from collections.abc import Callable, Iterable
from pathlib import Path

from vslsp.tasks.base import TrialResult
from vslsp.tasks.statistics import wilson_interval


def add_arguments(parser: argparse.ArgumentParser, groups: str) -> None:
    """A benchmark's options for its trials file: ``--workers``, ``--chunk`` (seeds per round of
    every one of ``groups``), ``--out``, ``--report-only`` and ``--json``."""
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--chunk", type=int, default=10, help=f"seeds per round of every {groups}")
    parser.add_argument(
        "--out",
        type=Path,
        default=None,
        help="a JSON-lines file of the trials: appended after each round, "
        "and the trials it holds already are not run again (resume)",
    )
    parser.add_argument("--report-only", action="store_true", help="run nothing: report the trials in --out")
    parser.add_argument("--json", action="store_true")


def read(path: Path | None) -> list[dict]:
    """The trials kept in ``path`` (none when it is None or does not exist yet)."""
    if path is None or not path.exists():
        return []
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


def trial_records(results: Iterable[TrialResult], **group) -> list[dict]:
    """One line per trial of ``results``: the ``group``'s fields, then the trial's."""
    return [
        {
            **group,
            "seed": r.seed,
            "success": r.success,
            "cpu_s": round(r.cpu_s, 3),
            "cause": None if r.success else r.cause,
            "error": r.error,
        }
        for r in results
    ]


def of(records: list[dict], group: dict) -> list[dict]:
    """The trials of ``records`` in ``group`` (every field of it equal)."""
    return [r for r in records if all(r.get(key) == value for key, value in group.items())]


def gather(
    args: argparse.Namespace,
    seeds: list[int],
    groups: list[dict],
    run: Callable[[dict, list[int], int], tuple[list[dict], bool]],
) -> list[dict]:
    """The trials of ``args.out`` (the options of :func:`add_arguments`), and unless
    ``--report-only`` those of ``seeds`` it lacks for each of ``groups``, run by
    ``run(group, seeds, workers)`` (:func:`run_rounds`)."""
    records = read(args.out)
    if not args.report_only:
        run_rounds(records, groups, seeds, args.chunk, lambda group, todo: run(group, todo, args.workers), args.out)
    return records


def run_rounds(
    records: list[dict],
    groups: list[dict],
    seeds: list[int],
    chunk: int,
    run: Callable[[dict, list[int]], tuple[list[dict], bool]],
    path: Path | None,
) -> None:
    """Run the trials of ``seeds`` that ``records`` lacks for each of ``groups``, in rounds of
    ``chunk`` seeds, each round every group; ``run(group, seeds)`` gives the new lines and
    whether Ctrl-C or SIGTERM stopped it (then the rounds end). Each group's new lines join
    ``records`` and are appended to ``path`` as they come; a line per round goes to stderr."""
    for start in range(0, len(seeds), chunk):
        for group in groups:
            done = {r["seed"] for r in of(records, group)}
            todo = [s for s in seeds[start : start + chunk] if s not in done]
            if not todo:
                continue
            new, stopped = run(group, todo)
            records.extend(new)
            words = " ".join(f"{key} {value}" for key, value in group.items())
            print(
                f"{words} seeds {todo[0]}-{todo[-1]}: {sum(r['success'] for r in new)}/{len(new)}",
                file=sys.stderr,
                flush=True,
            )
            if path is not None:
                with path.open("a") as stream:
                    stream.writelines(json.dumps(r) + "\n" for r in new)
            if stopped:  # the finished trials are kept; the report covers what ran
                return


def success_row(records: list[dict]) -> dict:
    """The success of ``records``: count, rate, its 95 % (Wilson) interval, the failures'
    causes and each failed seed's error."""
    successes = sum(r["success"] for r in records)
    low, high = wilson_interval(successes, len(records))
    return {
        "trials": len(records),
        "successes": successes,
        "rate": successes / len(records),
        "interval_95": [round(low, 3), round(high, 3)],
        "failures": dict(Counter(r["cause"] for r in records if not r["success"])),
        "failed": {r["seed"]: r["error"] for r in records if not r["success"]},
    }
