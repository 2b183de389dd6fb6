"""Running seeded trials on several processes (the experiments' ``--workers``)."""

from __future__ import annotations

from typing import Callable, Iterable, TypeVar

J = TypeVar("J")
R = TypeVar("R")


def run_jobs(function: Callable[[J], R], jobs: Iterable[J], workers: int = 1,
             on_done: Callable[[R], None] | None = None) -> list[R]:
    """``function`` on each job, on ``workers`` processes (spawned: pybullet and torch do not
    survive a fork), results in job order; ``on_done(result)`` as each one finishes (progress).
    ``function`` and the jobs must be picklable (a module-level function, plain values)."""
    jobs = list(jobs)
    if workers <= 1:
        results = []
        for job in jobs:
            results.append(function(job))
            if on_done:
                on_done(results[-1])
        return results
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed

    with ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("spawn")) as pool:
        futures = {pool.submit(function, job): k for k, job in enumerate(jobs)}
        done: dict[int, R] = {}
        for future in as_completed(futures):
            done[futures[future]] = future.result()
            if on_done:
                on_done(done[futures[future]])
    return [done[k] for k in range(len(jobs))]
