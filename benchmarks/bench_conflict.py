"""Conflict benchmark: vslsp.symbolic.validation.conflict.explain on unsolvable "pull every block in order" problems.

The order of the "Pull All Objects in a Given Order" experiment over N blocks (all far; goal:
none far; N-1 ``sometime-before`` constraints) made unsolvable in two ways:

- ``small``: one more constraint puts block 0 after block 1 (a two-cycle): no block can be
  pulled; the smallest conflict is 3 parts (the two constraints and block 0's goal conjunct),
  others take block k's goal conjunct and the chain up to k;
- ``whole``: one more constraint puts block 0 after block N-1 (a cycle through the whole chain);
  the only minimal conflicts are N+1 parts (every constraint and one goal conjunct).

Deletion finds *a* minimal conflict (irreducible: removing any part makes the rest solvable),
not always the smallest. For each problem, measured in the same run: the search (planner calls,
time, the set's size, whether it was proven minimal) and, as the reference, one planner call
on the whole problem (min of 3); the ratio says how many such calls the explanation costs.

Measured on the shared 2-core machine (2026-12-02, loaded by other jobs): N = 5, 10, 20:
small 3 / 7 / 12 parts found in 12 / 25 / 35 calls (11.6 / 11.6 / 17.0 s), whole 6 / 11 / 21
parts in 14 / 26 / 47 calls (6.4 / 16.5 / 30.7 s); one call 0.1-0.7 s.

    .venv/bin/python benchmarks/bench_conflict.py [--sizes 5 10 20 40] [--budget 120]
"""

from __future__ import annotations

import argparse
import time

from vslsp.errors import TaskFailed
from vslsp.symbolic import Atom, Domain, Not, Problem, SometimeBefore, read_domain, solve
from vslsp.symbolic.model.formula import conjunction
from vslsp.symbolic.validation.conflict import explain


def ordered_problem(domain: Domain, blocks: int, cycle: str) -> Problem:
    """``blocks`` far blocks pulled in order b0, b1, ..., with one constraint closing a cycle."""
    names = [f"b{i}" for i in range(blocks)]
    near = [Not(Atom("far", (name,))) for name in names]
    problem = Problem(f"order-{blocks}", domain).with_objects("block", *names)
    problem = problem.with_init(*(Atom("far", (name,)) for name in names)).with_goal(conjunction(near))
    for earlier, later in zip(near, near[1:], strict=False):
        problem = problem.with_constraint(SometimeBefore(later, earlier))
    last = 1 if cycle == "small" else blocks - 1
    return problem.with_constraint(SometimeBefore(near[0], near[last]))


def one_call_s(domain: Domain, problem: Problem) -> float:
    times = []
    for _ in range(3):
        start = time.perf_counter()
        try:
            solve(domain, problem)
        except TaskFailed:
            pass
        times.append(time.perf_counter() - start)
    return min(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--sizes", type=int, nargs="+", default=[5, 10, 20, 40])
    parser.add_argument("--budget", type=float, default=120.0, help="explain's budget_s (seconds)")
    args = parser.parse_args()
    from pathlib import Path

    domain = read_domain(Path(__file__).resolve().parents[1] / "pddl" / "domain.pddl")
    print(
        f"{'cycle':6} {'N':>4} {'parts':>6} {'found':>6} {'minimal':>8} {'calls':>6} {'time s':>8} "
        f"{'1 call s':>9} {'ratio':>6}"
    )
    for cycle in ("small", "whole"):
        for blocks in args.sizes:
            problem = ordered_problem(domain, blocks, cycle)
            reference = one_call_s(domain, problem)
            conflict = explain(domain, problem, budget_s=args.budget, known_unsolvable=True)
            assert conflict is not None
            parts = len(problem.constraints) + blocks
            print(
                f"{cycle:6} {blocks:>4} {parts:>6} {len(conflict.parts):>6} {conflict.minimal!s:>8} "
                f"{conflict.checks:>6} {conflict.time_s:>8.2f} {reference:>9.2f} {conflict.time_s / reference:>6.1f}"
            )


if __name__ == "__main__":
    main()
