"""Ray backend benchmark: the overhead of running an experiment's trials as Ray tasks.

The same experiment and seeds (default: house-roof, the paper's "Simulation" of VSL, 6 trials)
run, in the same process and interleaved so that both see the same machine load, on:

- ``local``: the runner's process pool with ``--workers`` processes (pool start included);
- ``ray``: a local Ray instance of ``--workers`` CPUs started for the run and shut down after
  (what ``vslsp experiment NAME --backend ray --workers W`` does; start included);
- ``ray, started``: the same instance already running (what a cluster user sees: the cluster's
  start is paid once, not per run).

Each figure is the minimum of ``--runs`` runs; the throughput ratio is local time / Ray time
(target: Ray within 15 % of local, ratio >= 0.85). It also states the data each trial sends and
receives (pickled bytes: the task once through the object store, then per trial the seed and the
task's object reference out and a result without artefacts back), and the driver's rate on
no-op trials (trials a second that one driver hands out and collects), from which scaling with
workers follows: W workers stay busy while W / trial time is below that rate.

    PYTHONPATH=. .venv/bin/python benchmarks/bench_ray.py [--experiment house-roof] [--trials 6] [--runs 2]
        [--workers 2] [--json results.json]
"""

from __future__ import annotations

import argparse
import json
import logging
import time

import ray
from ray import cloudpickle
from rich.console import Console
from rich.table import Table

from vslsp.tasks import System, Task, TrialResult, get_task, run_trials
from vslsp.tasks.ray_backend import run_on_ray

progress = Console(stderr=True)


class NoOp(Task):
    """A trial that does nothing: the driver's and Ray's cost per trial alone."""

    name = "no-op"
    system = System.VSL
    paper_section = "benchmark"

    def run_trial(self, seed: int, keep: bool = False) -> TrialResult:
        return TrialResult(self.name, seed, True)


def records(results: list[TrialResult]) -> list[dict]:
    """The trials' JSON records without times."""
    return [{k: v for k, v in r.to_dict().items() if k not in ("time_s", "reproduction_ms")} for r in results]


def timed_run(task: Task, seeds: list[int], workers: int, backend: str) -> tuple[float, list[TrialResult]]:
    start = time.perf_counter()
    run = run_trials(task, seeds, workers=workers, backend=backend)
    return time.perf_counter() - start, run.results


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--experiment", default="house-roof")
    parser.add_argument("--trials", type=int, default=6)
    parser.add_argument("--runs", type=int, default=2)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--noop", type=int, default=200, help="no-op trials for the driver's rate")
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    task = get_task(args.experiment)
    seeds = list(range(args.trials))
    times: dict[str, list[float]] = {"local": [], "ray": [], "ray, started": []}
    results: dict[str, list[TrialResult]] = {}
    for run in range(args.runs):
        for backend in times:
            progress.print(f"run {run + 1}/{args.runs}: {backend}")
            if backend == "ray, started":
                ray.init(
                    address="local",
                    num_cpus=args.workers,
                    include_dashboard=False,
                    log_to_driver=False,
                    logging_level=logging.ERROR,
                )
                try:
                    seconds, results[backend] = timed_run(task, seeds, args.workers, "ray")
                finally:
                    ray.shutdown()
            else:
                seconds, results[backend] = timed_run(task, seeds, args.workers, backend)
            times[backend].append(seconds)
    same = all(records(results[b]) == records(results["local"]) for b in times)

    # The driver's rate: no-op trials on a started instance (the start excluded).
    ray.init(
        address="local",
        num_cpus=args.workers,
        include_dashboard=False,
        log_to_driver=False,
        logging_level=logging.ERROR,
    )
    try:
        done: list[TrialResult] = []
        run_on_ray(NoOp(), list(range(20)), set(), args.workers, None, done.append)  # warm the workers
        start = time.perf_counter()
        run_on_ray(NoOp(), list(range(args.noop)), set(), args.workers, None, done.append)
        rate = args.noop / (time.perf_counter() - start)
    finally:
        ray.shutdown()

    task_bytes = len(cloudpickle.dumps(task))
    sent = len(cloudpickle.dumps((seeds[-1], False)))  # per trial, beside the task's 28-byte object id
    received = [len(cloudpickle.dumps(r.without_artefacts())) for r in results["local"]]
    best = {b: min(t) for b, t in times.items()}
    mean_trial = sum(r.time_s for r in results["local"]) / len(seeds)
    table = Table(title=f"{args.experiment}: {args.trials} trials, {args.workers} workers, min of {args.runs} runs")
    for column in ("backend", "seconds (min)", "all runs", "trials/s", "throughput vs local"):
        table.add_column(column)
    for backend, seconds in best.items():
        table.add_row(
            backend,
            f"{seconds:.1f}",
            ", ".join(f"{t:.1f}" for t in times[backend]),
            f"{args.trials / seconds:.3f}",
            f"{best['local'] / seconds:.2f}",
        )
    console = Console()
    console.print(table)
    console.print(f"same per-trial results on every backend (times excepted): {'yes' if same else 'NO'}")
    console.print(
        f"data: the task once to the object store: {task_bytes} B pickled; per trial sent: {sent} B "
        f"(seed, keep) + a 28-byte object id; per trial received: a result without artefacts, "
        f"{min(received)}-{max(received)} B (mean {sum(received) / len(received):.0f} B)"
    )
    console.print(
        f"driver: {rate:.0f} no-op trials/s on {args.workers} CPUs; mean trial {mean_trial:.1f} s, so one "
        f"driver keeps about {rate * mean_trial:.0f} workers busy (linear scaling up to there)"
    )
    if args.json:
        with open(args.json, "w") as handle:
            json.dump(
                {
                    "experiment": args.experiment,
                    "trials": args.trials,
                    "workers": args.workers,
                    "runs": args.runs,
                    "seconds": times,
                    "best": best,
                    "throughput_ratio_ray": best["local"] / best["ray"],
                    "throughput_ratio_ray_started": best["local"] / best["ray, started"],
                    "same_results": same,
                    "task_bytes": task_bytes,
                    "sent_per_trial_bytes": sent,
                    "received_per_trial_bytes": received,
                    "driver_noop_trials_per_s": rate,
                    "mean_trial_s": mean_trial,
                },
                handle,
                indent=2,
            )


if __name__ == "__main__":
    main()
