"""The planner's bound: a problem that makes Fast Downward grow without end stops at the limits.

The problem (``tests/data/limits/forall-or.pddl``, issue 27): three nested ``forall`` over an
``or`` of three atoms in the goal. Fast Downward's translator turns the goal into its
disjunctive normal form and grew past 20 GB before it was killed by hand. vslsp runs every
planner under a default time and memory limit (``vslsp.symbolic.engines.planner.DEFAULT_TIMEOUT_S``,
``DEFAULT_MEMORY_MB``; ``vslsp plan --timeout / --memory``). Measured here, in one run:

- the outcome (expected: exit 1, "memory limit of N MB reached") and the wall-clock time
  against the time limit;
- the peak resident memory of the planner's process tree (the driver, the translator, the
  search: their RSS summed, sampled every 10 ms from ``/proc``) against the memory limit;
- the same for the solvable ``pddl/pull-in-order.pddl`` (the limits cost a plan nothing).

Measured on the shared 2-core machine (2026-12-02, one run, load about 6): the forall goal ends
with exit 1, "memory limit of 4096 MB reached", after 135 s (0.45 of the time limit; 91 s with
the machine less loaded), its tree's peak RSS 4063 MB (0.99 of the limit; without a limit it
grew past 20 GB); pull-in-order plans 3 steps in 0.7 s, 38 MB.

    .venv/bin/python benchmarks/bench_planner_limits.py [--memory MB] [--timeout S]
"""

from __future__ import annotations

import argparse
import os
import threading
import time
from pathlib import Path

from vslsp.errors import VslspError
from vslsp.symbolic import read_pddl, solve
from vslsp.symbolic.engines.fast_downward import descendants
from vslsp.symbolic.engines.planner import DEFAULT_MEMORY_MB, DEFAULT_TIMEOUT_S

ROOT = Path(__file__).resolve().parents[1]
DOMAIN = ROOT / "pddl" / "domain.pddl"
PROBLEMS = {
    "forall-or (issue 27)": ROOT / "tests" / "data" / "limits" / "forall-or.pddl",
    "pull-in-order": ROOT / "pddl" / "pull-in-order.pddl",
}


def tree_rss_mb() -> float:
    """The resident memory of this process's children and their children, summed (MB)."""
    total = 0
    for pid in descendants(os.getpid()):
        try:
            with open(f"/proc/{pid}/status") as status:
                for line in status:
                    if line.startswith("VmRSS:"):
                        total += int(line.split()[1])
        except OSError:  # it ended meanwhile
            continue
    return total / 1024


def measure(problem_file: Path, timeout: float, memory_mb: int) -> dict:
    """Plan once while a thread samples the planner tree's memory; outcome, time and peak."""
    domain, problem = read_pddl(DOMAIN, problem_file)
    assert problem is not None
    peak = [0.0]
    done = threading.Event()

    def sample() -> None:
        while not done.wait(0.01):
            peak[0] = max(peak[0], tree_rss_mb())

    sampler = threading.Thread(target=sample, daemon=True)
    sampler.start()
    start = time.perf_counter()
    try:
        outcome = f"plan of {len(solve(domain, problem, timeout=timeout, memory_mb=memory_mb).steps)} steps"
        code = 0
    except VslspError as error:
        outcome, code = str(error), error.exit_code
    elapsed = time.perf_counter() - start
    done.set()
    sampler.join()
    return {"outcome": outcome, "exit_code": code, "time_s": elapsed, "peak_rss_mb": peak[0]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--memory", type=int, default=DEFAULT_MEMORY_MB, help="memory limit, MB (default: vslsp's)")
    parser.add_argument("--timeout", type=float, default=DEFAULT_TIMEOUT_S, help="time limit, s (default: vslsp's)")
    args = parser.parse_args()
    print(f"limits: {args.timeout:g} s, {args.memory} MB per process of the planner")
    print(f"{'problem':<22} {'exit':>4} {'time (s)':>9} {'/limit':>7} {'peak RSS (MB)':>14} {'/limit':>7}  outcome")
    for name, path in PROBLEMS.items():
        row = measure(path, args.timeout, args.memory)
        print(
            f"{name:<22} {row['exit_code']:>4} {row['time_s']:>9.2f} {row['time_s'] / args.timeout:>7.3f} "
            f"{row['peak_rss_mb']:>14.0f} {row['peak_rss_mb'] / args.memory:>7.3f}  {row['outcome']}"
        )


if __name__ == "__main__":
    main()
