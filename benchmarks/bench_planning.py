"""Planning benchmark: vslsp.symbolic.solve on "pull every block", with and without the order.

The problem of the "Pull All Objects in a Given Order" experiment grown to N blocks (all far;
goal: none far), once with the full chain of N-1 ``sometime-before`` constraints (the
demonstrated order) and once without. For each N, measured in the same run:

- parse: reading the written domain + problem files through unified-planning's PDDLReader;
- build / compile / solve: our model to UP, TrajectoryConstraintsRemover, Fast Downward;
- reference: Fast Downward's own driver run directly on the constraint-free files (no UP, the
  same search), and the ratios of our chained and free times to it; and LAMA (lama-first,
  ``fast-downward-lama``) on the chained problem;
- validate: our validator on the plan found (and a check that the plan keeps the order).

Target (issue 4): ≤ 2 s at 100 blocks with the full chain.

    .venv/bin/python benchmarks/bench_planning.py [--sizes 5 20 50 100 200] [--json results.json]
"""

from __future__ import annotations

import argparse
import importlib.resources
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from rich.console import Console
from rich.table import Table

from vslsp.symbolic import Atom, Domain, Not, Problem, SometimeBefore, forall, read_pddl, save, solve, solve_timed, validate
from vslsp.symbolic.planner import DEFAULT_PLANNER, PLANNERS

progress = Console(stderr=True)


def pull_in_order(domain: Domain, n: int, ordered: bool) -> Problem:
    """N blocks b01..bN, all far; goal: no block far; ordered: b01 first, then b02, ..."""
    blocks = [f"b{i:03d}" for i in range(1, n + 1)]
    problem = Problem(f"pull-{n}{'-ordered' if ordered else ''}", domain).with_objects("block", *blocks)
    problem = problem.with_init(*(Atom("far", (b,)) for b in blocks)).with_goal(forall(("?b", "block"), Not(Atom("far", ("?b",)))))
    if ordered:
        for earlier, later in zip(blocks, blocks[1:]):
            problem = problem.with_constraint(SometimeBefore(Not(Atom("far", (later,))), Not(Atom("far", (earlier,)))))
    return problem


def fast_downward_directly(domain_file: Path, problem_file: Path) -> float:
    """Seconds for Fast Downward's driver on the files, no UP (the search of our default planner)."""
    driver = importlib.resources.files("up_fast_downward").joinpath("downward/fast-downward.py")
    with tempfile.TemporaryDirectory() as folder:
        # Fast Downward's translator rejects the PDDL 3.0 requirement; this problem has no constraints.
        plain = save(domain_file.read_text().replace(" :constraints", ""), Path(folder) / "domain.pddl")
        start = time.perf_counter()
        search = PLANNERS[DEFAULT_PLANNER][1]["fast_downward_search_config"]
        subprocess.run([sys.executable, str(driver), str(plain), str(problem_file), "--search", search],
                       cwd=folder, check=True, capture_output=True)
        return time.perf_counter() - start


def measure(domain_file: Path, n: int, folder: Path) -> dict:
    domain, _ = read_pddl(domain_file)
    row: dict = {"blocks": n}
    for ordered in (True, False):
        key = "chain" if ordered else "free"
        problem_file = save(pull_in_order(domain, n, ordered).to_pddl(), folder / f"p{n}-{key}.pddl")
        start = time.perf_counter()
        read_domain, problem = read_pddl(domain_file, problem_file)
        parse = time.perf_counter() - start
        assert problem is not None
        plan, times = solve_timed(read_domain, problem)
        start = time.perf_counter()
        verdict = validate(read_domain, problem, plan.steps)
        row[key] = {"parse_s": parse, "build_s": times.build_s, "compile_s": times.compile_s,
                    "solve_s": times.solve_s, "total_s": parse + plan.time_s,
                    "validate_s": time.perf_counter() - start, "steps": len(plan.steps), "valid": verdict.valid}
        if ordered:
            row["chain_lama_s"] = solve(read_domain, problem, "fast-downward-lama").time_s
            row["keeps_order"] = [args[0] for _, args in plan.steps] == sorted(o for o, _ in problem.objects)
        else:
            row["fast_downward_direct_s"] = fast_downward_directly(domain_file, problem_file)
    return row


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[3, 5, 10, 20, 30, 50, 100, 200])
    parser.add_argument("--json", type=Path, default=None, help="Also write the figures there.")
    args = parser.parse_args()
    domain_file = Path(__file__).resolve().parents[1] / "pddl" / "domain.pddl"

    start = time.perf_counter()
    import unified_planning.shortcuts  # noqa: F401  (the cold start, measured once)

    cold_import = time.perf_counter() - start
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        start = time.perf_counter()
        measure(domain_file, 3, Path(tmp))  # first plan: engine classes loaded, FD binaries in cache
        first = time.perf_counter() - start
        for n in args.sizes:
            with progress.status(f"{n} blocks"):
                rows.append(measure(domain_file, n, Path(tmp)))

    table = Table(title=f"vslsp.symbolic.solve: pull N blocks ({DEFAULT_PLANNER}: greedy FF), seconds; "
                        "total = parse + build + compile + solve")
    for column in ("N", "chain parse", "build", "compile", "solve", "chain total", "free total",
                   "FD direct", "chain/FD", "free/FD", "chain LAMA plan", "validate", "order kept"):
        table.add_column(column, justify="right")
    for row in rows:
        chain, free, direct = row["chain"], row["free"], row["fast_downward_direct_s"]
        table.add_row(str(row["blocks"]), f"{chain['parse_s']:.3f}", f"{chain['build_s']:.3f}",
                      f"{chain['compile_s']:.3f}", f"{chain['solve_s']:.3f}", f"{chain['total_s']:.3f}",
                      f"{free['total_s']:.3f}", f"{direct:.3f}", f"{chain['total_s'] / direct:.2f}x",
                      f"{free['total_s'] / direct:.2f}x", f"{row['chain_lama_s']:.3f}", f"{chain['validate_s']:.3f}",
                      "yes" if row["keeps_order"] and chain["valid"] and free["valid"] else "NO")
    console = Console(width=170)
    console.print(table)
    console.print("FD direct: Fast Downward's driver on the constraint-free files, same search, no UP; "
                  "chain LAMA plan: build + compile + solve with fast-downward-lama (lama-first)")
    console.print(f"cold start: import unified_planning {cold_import:.2f} s; first plan (3 blocks, both problems "
                  f"and the FD reference) {first:.2f} s")
    at_100 = [r for r in rows if r["blocks"] == 100]
    if at_100:
        chain = at_100[0]["chain"]
        planning = chain["total_s"] - chain["parse_s"]
        console.print(f"target: 100 blocks with the full chain in <= 2 s: planning (build + compile + solve) "
                      f"{planning:.2f} s ({'met' if planning <= 2.0 else 'NOT met'}), with parsing {chain['total_s']:.2f} s")
    if args.json:
        args.json.write_text(json.dumps({"cold_import_s": cold_import, "first_plan_s": first, "rows": rows}, indent=1))


if __name__ == "__main__":
    main()
