"""Planning benchmark: vslsp.symbolic.solve on "pull every block", with and without the order,
and a PDDL 3 suite of public constrained problems (``--suite pddl3``).

The problem of the "Pull All Objects in a Given Order" experiment grown to N blocks (all far;
goal: none far), once with the full chain of N-1 ``sometime-before`` constraints (the
demonstrated order) and once without. For each N, measured in the same run:

- parse: reading the written domain + problem files through unified-planning's PDDLReader;
- build / compile / solve: our model to UP, TrajectoryConstraintsRemover, Fast Downward;
- reference: Fast Downward's own driver run directly on the constraint-free files (no UP, the
  same search), and the ratios of our chained and free times to it; and LAMA (lama-first,
  ``fast-downward-lama``) on the chained problem;
- validate: our validator on the plan found (and a check that the plan keeps the order).

Targets: ≤ 2 s of planning at 100 blocks (issue 4) and at 200 blocks (issue 16) with the full chain.

PDDL 3 suite (``--suite pddl3``): every problem under tests/data/pddl3 (LiftedTCORE's blocksworld
and sokoban with hard constraints; IPC-2006 qualitative preferences, read with the preferences
ignored). Per problem, in the same run: reading, the lifted compilation (``compile``: monitors
into the schemas and the PDDL text), Fast Downward on the compiled problem (``plan``, 60 s
limit), plan length, our validator and VAL (when the ``VAL`` environment variable names VAL's
``Validate`` binary; the problem is handed to it as vslsp writes it, constraints under
``(and ...)``, since VAL drops a bare list); as the reference, Fast Downward on the same problem
without its constraints (plan) and its translator alone (``FD translate``). Targets (issue 16):
no crash, >= 80 % planned within 60 s, every plan valid, compile <= 2x FD translate.

Measured on the shared 2-core machine (one run each, 2026-12-01): chain, planning at 200 blocks
1.09 s (100: 0.75 s), parsing 3.0 s more; PDDL 3 suite, 49 of 50 constrained problems planned
within 60 s (blocksworld p26 runs out of time; the slowest planned: 35.5 s), 49 of 49 plans valid
for vslsp and for VAL, median plan 0.51 s against 0.37 s without the constraints, compile at most
0.21x Fast Downward's translator on the unconstrained problem (12 ms at most); the 12 IPC-2006
problems read and planned with their preferences ignored.

    .venv/bin/python benchmarks/bench_planning.py [--sizes 5 20 50 100 200] [--json results.json]
    VAL=/path/to/Validate .venv/bin/python benchmarks/bench_planning.py --suite pddl3 [--only sokoban]
"""

from __future__ import annotations

import argparse
import importlib.resources
import json
import os
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

from rich.console import Console
from rich.table import Table

from vslsp.errors import VslspError
from vslsp.symbolic import (
    Atom,
    Domain,
    Not,
    PddlWarning,
    Problem,
    SometimeBefore,
    forall,
    read_pddl,
    save,
    solve,
    solve_timed,
    validate,
)
from vslsp.symbolic.engines import fast_downward
from vslsp.symbolic.engines.lifted import compile_lifted
from vslsp.symbolic.engines.planner import DEFAULT_PLANNER, PLANNERS, planner_texts

SUITE = Path(__file__).resolve().parents[1] / "tests" / "data" / "pddl3"

progress = Console(stderr=True)


def pull_in_order(domain: Domain, n: int, ordered: bool) -> Problem:
    """N blocks b01..bN, all far; goal: no block far; ordered: b01 first, then b02, ..."""
    blocks = [f"b{i:03d}" for i in range(1, n + 1)]
    problem = Problem(f"pull-{n}{'-ordered' if ordered else ''}", domain).with_objects("block", *blocks)
    problem = problem.with_init(*(Atom("far", (b,)) for b in blocks))
    problem = problem.with_goal(forall(("?b", "block"), Not(Atom("far", ("?b",)))))
    if ordered:
        for earlier, later in zip(blocks, blocks[1:], strict=False):
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
        subprocess.run(
            [sys.executable, str(driver), str(plain), str(problem_file), "--search", search],
            cwd=folder,
            check=True,
            capture_output=True,
        )
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
        row[key] = {
            "parse_s": parse,
            "build_s": times.build_s,
            "compile_s": times.compile_s,
            "solve_s": times.solve_s,
            "total_s": parse + plan.time_s,
            "validate_s": time.perf_counter() - start,
            "steps": len(plan.steps),
            "valid": verdict.valid,
        }
        if ordered:
            row["chain_lama_s"] = solve(read_domain, problem, "fast-downward-lama").time_s
            row["keeps_order"] = [args[0] for _, args in plan.steps] == sorted(o for o, _ in problem.objects)
        else:
            row["fast_downward_direct_s"] = fast_downward_directly(domain_file, problem_file)
    return row


def suite_problems(only: str) -> list[tuple[Path, Path]]:
    cases = []
    for domain in sorted(SUITE.glob("*/*/domain.pddl")):
        problems = [p for p in domain.parent.glob("*.pddl") if p.name != "domain.pddl" and only in str(p)]
        cases += [(domain, p) for p in sorted(problems, key=lambda p: (len(p.name), p.name))]
    return cases


def val_verdict(domain: Domain, problem: Problem, domain_file: Path, steps: list[str]) -> str:
    """VAL's verdict ("valid"/"INVALID"/"-" without VAL) on the plan, against the problem as vslsp writes it."""
    binary = os.environ.get("VAL")
    if not binary:
        return "-"
    with tempfile.TemporaryDirectory() as folder:
        problem_file = save(problem.to_pddl(), Path(folder) / "problem.pddl")
        plan_file = save("".join(f"({s})\n" for s in steps), Path(folder) / "plan")
        done = subprocess.run(
            [binary, str(domain_file), str(problem_file), str(plan_file)], capture_output=True, text=True, timeout=120
        )
        return "valid" if done.returncode == 0 and "Plan valid" in done.stdout else "INVALID"


def measure_problem(domain_file: Path, problem_file: Path, timeout: float) -> dict:
    row: dict = {"problem": str(problem_file.relative_to(SUITE))}
    try:
        start = time.perf_counter()
        domain, problem = read_pddl(domain_file, problem_file)
        assert problem is not None
        row.update(read_s=time.perf_counter() - start, constraints=len(problem.constraints))
        start = time.perf_counter()
        planner_texts(*compile_lifted(domain, problem))
        row["compile_s"] = time.perf_counter() - start
        free_texts = planner_texts(domain, problem.without_constraints())
        row["fd_translate_s"] = min(_translate(*free_texts) for _ in range(3))
        try:
            row["free_plan_s"] = solve(domain, problem.without_constraints(), timeout=timeout).time_s
        except VslspError as error:
            row["free_plan_s"], row["free_error"] = None, str(error)
        plan = solve(domain, problem, timeout=timeout)
        row.update(
            plan_s=plan.time_s,
            steps=len(plan.steps),
            compilation=plan.compilation.value,
            valid=validate(domain, problem, plan).valid,
            val=val_verdict(domain, problem, domain_file, plan.lines()),
        )
    except VslspError as error:
        row.update(error=f"{type(error).__name__}: {error}")
    return row


def _translate(domain_text: str, problem_text: str) -> float:
    """Fast Downward's translator alone (wall-clock, from its log; the run's time if the log has none)."""
    run = fast_downward.run(domain_text, problem_text, [], translate_only=True)
    return run.translate_s if run.translate_s is not None else run.time_s


def run_suite(only: str, timeout: float, json_path: Path | None) -> None:
    warnings.simplefilter("ignore", PddlWarning)  # bare constraint lists, preferences: expected in these files
    rows = []
    for domain_file, problem_file in suite_problems(only):
        with progress.status(str(problem_file.relative_to(SUITE))):
            rows.append(measure_problem(domain_file, problem_file, timeout))
    table = Table(
        title=f"PDDL 3 suite: lifted constraint compilation + Fast Downward ({DEFAULT_PLANNER}), seconds; "
        f"limit {timeout:g} s per problem"
    )
    for column in (
        "problem",
        "constr.",
        "read",
        "compile",
        "FD translate (free)",
        "compile/translate",
        "plan",
        "free plan",
        "steps",
        "valid",
        "VAL",
    ):
        table.add_column(column, justify="right")
    for row in rows:
        if "error" in row:
            table.add_row(
                row["problem"], str(row.get("constraints", "")), "", "", "", "", row["error"][:60], "", "", "", ""
            )
            continue
        ratio = row["compile_s"] / row["fd_translate_s"]
        free = f"{row['free_plan_s']:.2f}" if row["free_plan_s"] is not None else "none"
        table.add_row(
            row["problem"],
            str(row["constraints"]),
            f"{row['read_s']:.2f}",
            f"{row['compile_s']:.3f}",
            f"{row['fd_translate_s']:.3f}",
            f"{ratio:.2f}x",
            f"{row['plan_s']:.2f}",
            free,
            str(row["steps"]),
            "yes" if row["valid"] else "NO",
            row["val"],
        )
    console = Console(width=180)
    console.print(table)
    constrained = [r for r in rows if r.get("constraints")]
    planned = [r for r in constrained if "error" not in r and r["plan_s"] <= timeout]  # wall-clock
    crashed = [r for r in rows if r.get("error", "").startswith(("InternalError", "AssertionError"))]
    ratios = [r["compile_s"] / r["fd_translate_s"] for r in rows if "compile_s" in r]
    console.print(
        f"constrained problems: {len(planned)} of {len(constrained)} planned within {timeout:g} s "
        f"({100 * len(planned) / max(1, len(constrained)):.0f} %); "
        f"crashes (internal errors): {len(crashed)}; "
        f"plans valid (vslsp): {sum(r['valid'] for r in planned)} of {len(planned)}; "
        f"VAL: {sum(r['val'] == 'valid' for r in planned)} valid of {len(planned)}"
        f"{' (VAL not given)' if not os.environ.get('VAL') else ''}"
    )
    if ratios:
        console.print(
            f"compile / FD translate (unconstrained): max {max(ratios):.2f}x, median "
            f"{sorted(ratios)[len(ratios) // 2]:.2f}x (target <= 2x)"
        )
    if json_path:
        json_path.write_text(json.dumps({"suite": rows}, indent=1))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[3, 5, 10, 20, 30, 50, 100, 200])
    parser.add_argument("--json", type=Path, default=None, help="Also write the figures there.")
    parser.add_argument("--suite", choices=["chain", "pddl3"], default="chain")
    parser.add_argument("--only", default="", help="pddl3 suite: only problems whose path contains this.")
    parser.add_argument("--timeout", type=float, default=60.0, help="pddl3 suite: seconds per problem.")
    args = parser.parse_args()
    if args.suite == "pddl3":
        run_suite(args.only, args.timeout, args.json)
        return
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

    table = Table(
        title=f"vslsp.symbolic.solve: pull N blocks ({DEFAULT_PLANNER}: greedy FF), seconds; "
        "total = parse + build + compile + solve"
    )
    for column in (
        "N",
        "chain parse",
        "build",
        "compile",
        "solve",
        "chain total",
        "free total",
        "FD direct",
        "chain/FD",
        "free/FD",
        "chain LAMA plan",
        "validate",
        "order kept",
    ):
        table.add_column(column, justify="right")
    for row in rows:
        chain, free, direct = row["chain"], row["free"], row["fast_downward_direct_s"]
        table.add_row(
            str(row["blocks"]),
            f"{chain['parse_s']:.3f}",
            f"{chain['build_s']:.3f}",
            f"{chain['compile_s']:.3f}",
            f"{chain['solve_s']:.3f}",
            f"{chain['total_s']:.3f}",
            f"{free['total_s']:.3f}",
            f"{direct:.3f}",
            f"{chain['total_s'] / direct:.2f}x",
            f"{free['total_s'] / direct:.2f}x",
            f"{row['chain_lama_s']:.3f}",
            f"{chain['validate_s']:.3f}",
            "yes" if row["keeps_order"] and chain["valid"] and free["valid"] else "NO",
        )
    console = Console(width=170)
    console.print(table)
    console.print(
        "FD direct: Fast Downward's driver on the constraint-free files, same search, no UP; "
        "chain LAMA plan: build + compile + solve with fast-downward-lama (lama-first)"
    )
    console.print(
        f"cold start: import unified_planning {cold_import:.2f} s; first plan (3 blocks, both problems "
        f"and the FD reference) {first:.2f} s"
    )
    for size in (100, 200):
        for row in (r for r in rows if r["blocks"] == size):
            chain = row["chain"]
            planning = chain["total_s"] - chain["parse_s"]
            console.print(
                f"target: {size} blocks with the full chain in <= 2 s: planning (build + compile + solve) "
                f"{planning:.2f} s ({'met' if planning <= 2.0 else 'NOT met'}), with parsing "
                f"{chain['total_s']:.2f} s"
            )
    if args.json:
        args.json.write_text(json.dumps({"cold_import_s": cold_import, "first_plan_s": first, "rows": rows}, indent=1))


if __name__ == "__main__":
    main()
