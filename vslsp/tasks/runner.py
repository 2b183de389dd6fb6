"""The one trial runner: seeded trials of any registered task, in parallel, results in seed order.

Backends: ``local`` runs the trials in this process (one worker) or on a pool of spawned
processes (pybullet and torch do not survive a fork); ``ray`` runs each trial as a Ray task
(:mod:`vslsp.tasks.ray_backend`). Whatever the backend:

- the same seed gives the same result (a trial builds everything from its seed);
- a trial that raises is recorded as a failed trial with the error, never lost;
- a worker process that dies is replaced and its trial retried once, then recorded as failed;
- Ctrl-C or SIGTERM stops at once: outstanding trials are cancelled, every worker ends, and
  the trials that finished are returned (``Run.interrupted``) so that their report is written.
"""

from __future__ import annotations

import multiprocessing
import os
import signal
from collections.abc import Callable, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from typing import Any

from vslsp import interrupts
from vslsp.errors import InputError
from vslsp.tasks.base import Task, TrialResult, TrialStatus
from vslsp.tasks.task_files import check_main_guard
from vslsp.tasks.trial import Interrupted, run_one

__all__ = ["BACKENDS", "Interrupted", "Run", "check_counts", "run_one", "run_trials"]

BACKENDS = ("local", "ray")


@dataclass
class Run:
    """The outcome of :func:`run_trials`: the finished trials in seed order, and whether the run
    was cut short (``interrupted``: the signal's name) before every seed ran."""

    results: list[TrialResult]
    seeds: list[int]
    interrupted: str | None = None

    @property
    def partial(self) -> bool:
        return len(self.results) < len(self.seeds)


def check_counts(trials: int, workers: int) -> None:
    """--trials and --workers must be at least 1."""
    if trials < 1:
        raise InputError(f"--trials must be at least 1, got {trials}")
    if workers < 1:
        raise InputError(f"--workers must be at least 1, got {workers}")


def run_trials(
    task: Task,
    seeds: Sequence[int],
    *,
    workers: int = 1,
    backend: str = "local",
    address: str | None = None,
    on_done: Callable[[TrialResult], None] | None = None,
    on_interrupt: Callable[[str], None] | None = None,
) -> Run:
    """Run the trials of ``seeds`` on ``backend`` with ``workers`` in parallel.

    ``on_done(result)`` is called as each trial finishes (in any order: progress);
    ``on_interrupt(signal_name)`` as soon as an interrupt arrives. The first seed keeps its
    artefacts when the task asks for it (``Task.keep_first``).
    """
    seeds = list(seeds)
    check_counts(len(seeds), workers)
    if backend not in BACKENDS:
        raise InputError(f"unknown backend {backend!r}; choose one of {', '.join(BACKENDS)}")
    if backend == "local" and len(seeds) > 1:
        check_main_guard(workers)  # before any work: workers would run an unguarded script again
    keep = {seeds[0]} if task.keep_first else set()
    done: dict[int, TrialResult] = {}

    def finished(result: TrialResult) -> None:
        done[result.seed] = result
        if on_done is not None:
            on_done(result)

    interrupted = None
    with interrupts.handled() as received:
        try:
            if backend == "ray":
                from vslsp.tasks.ray_backend import run_on_ray

                run_on_ray(task, seeds, keep, workers, address, finished)
            elif workers == 1 or len(seeds) == 1:
                for seed in seeds:
                    finished(run_one(task, seed, seed in keep))
            else:
                _run_pool(task, seeds, keep, workers, finished)
        except (Interrupted, KeyboardInterrupt) as stop:
            interrupted = received[0] if received else getattr(stop, "signal_name", "SIGINT")
            if on_interrupt is not None:
                on_interrupt(interrupted)
    return Run([done[s] for s in seeds if s in done], seeds, interrupted)


_parent = 0  # in a pool worker: the driver's pid


def _worker_init(parent: int) -> None:
    global _parent
    # The parent handles Ctrl-C, SIGHUP and SIGQUIT for all (and ends the workers); a worker must
    # not die of them half-way.
    for number in (signal.SIGINT, signal.SIGHUP, signal.SIGQUIT):
        signal.signal(number, signal.SIG_IGN)
    # A worker ends with its driver however the driver ends (SIGKILL too): the kernel sends it
    # SIGTERM, which ends the trial's planner and removes its folder on the way out (then the
    # worker exits at once: nobody is left to report to).
    _parent = parent
    interrupts.die_with_parent(signal.SIGTERM, parent)
    # The parent ends a worker with SIGTERM: raised, so that the planner it may be running is
    # killed and its temporary folders removed on the way out.
    signal.signal(signal.SIGTERM, _raise_interrupted)
    from vslsp.sim.quiet import quiet  # noqa: F401  (workers import the simulator quietly)


_in_trial = False  # in a pool worker: whether a trial runs now


def _trial_in_worker(task: Task, seed: int, keep: bool) -> TrialResult:
    """:func:`run_one` in a pool worker, noting that a trial runs (for :func:`_raise_interrupted`)."""
    global _in_trial, _stopping
    _in_trial, _stopping = True, False  # once per trial: a worker told to stop may get the next queued one
    try:
        return run_one(task, seed, keep)
    finally:
        _in_trial = False
        if interrupts.orphaned(_parent):  # the driver is gone: nobody to report to, nothing to print
            os._exit(128 + signal.SIGTERM)


_stopping = False  # in a pool worker: whether a signal already raised in the trial running now


def _raise_interrupted(number: int, frame: Any) -> None:
    global _stopping
    if not _in_trial:
        # A worker starting or waiting for its next trial has nothing to clean up; raising there
        # would print the pool loop's traceback on the user's terminal.
        os._exit(128 + number)
    if interrupts.postponed(number):  # a planner being killed: the signal comes again after it
        return
    if _stopping:
        # Once, as in the driver (interrupts.handled): the first signal's cleanup (the planner
        # killed, its folder removed) runs to its end. A worker gets two when its driver ends it
        # and then exits (its parent-death signal).
        return
    _stopping = True
    raise Interrupted(signal.Signals(number).name)


def _new_pool(workers: int) -> ProcessPoolExecutor:
    # One thread per worker for torch/OpenMP: the workers already share the cores (spawned
    # children take the environment as it is when they start).
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    return ProcessPoolExecutor(
        max_workers=workers,
        mp_context=multiprocessing.get_context("spawn"),
        initializer=_worker_init,
        initargs=(os.getpid(),),
    )


def _end_pool(pool: ProcessPoolExecutor) -> None:
    """Stop a pool now: cancel what has not started and terminate its processes."""
    processes = list(getattr(pool, "_processes", {}).values())  # the executor offers no kill
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        if process.is_alive():
            process.terminate()
    for process in processes:
        process.join(timeout=5)
        if process.is_alive():
            process.kill()


def _run_pool(
    task: Task, seeds: list[int], keep: set[int], workers: int, finished: Callable[[TrialResult], None]
) -> None:
    """Trials on a process pool, at most ``workers`` in flight (so that when a worker dies,
    the trials it may have been running are known and retried once in a fresh pool)."""
    queue = list(seeds)
    retried: set[int] = set()
    pool = _new_pool(workers)
    running: dict[Future, int] = {}
    try:
        while queue or running:
            # A retried trial runs alone, so that a second death is its own and no other trial's.
            while (
                queue
                and len(running) < workers
                and not (running and (queue[0] in retried or any(s in retried for s in running.values())))
            ):
                seed = queue.pop(0)
                running[pool.submit(_trial_in_worker, task, seed, seed in keep)] = seed
            completed: set[Future] = set()
            while not completed:  # in slices: a signal is acted upon within one (interrupts.WAIT_SLICE_S)
                completed, _ = wait(list(running), timeout=interrupts.WAIT_SLICE_S, return_when=FIRST_COMPLETED)
            broken = []
            for future in completed:
                seed = running.pop(future)
                try:
                    finished(future.result())
                except BrokenProcessPool:
                    broken.append(seed)
                except Interrupted as stop:  # the worker alone was sent SIGTERM (by someone else)
                    ended = f"worker ended by {stop.signal_name}"
                    finished(TrialResult(task.name, seed, False, ended, failure_cause=ended, status=TrialStatus.LOST))
            if broken:
                # Every trial in flight was lost with the pool: retry each once in a fresh one.
                lost = sorted(broken + list(running.values()))
                running.clear()
                _end_pool(pool)
                pool = _new_pool(workers)
                for seed in lost:
                    if seed in retried:
                        finished(
                            TrialResult(
                                task.name,
                                seed,
                                False,
                                "worker died: its process ended during the trial twice (crash or out of memory)",
                                failure_cause="worker died",
                                status=TrialStatus.LOST,
                            )
                        )
                    else:
                        retried.add(seed)
                        queue.insert(0, seed)
    finally:
        _end_pool(pool)
