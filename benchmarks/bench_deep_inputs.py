"""Deep and huge PDDL input (issue 42): the time and the peak memory of each command on each case.

Every case an attacker measured, and its neighbour at the limit, is written to a temporary folder and
run as a user runs it (``python -m vslsp ...``, a fresh process each, its address space limited to
4 GB and its wall clock to 150 s); printed: the exit code, the wall-clock seconds, the process's peak
resident memory (``ru_maxrss`` from ``wait4``) and the first line of its message. The limits are
``vslsp.symbolic.budget``'s; tests/cli/test_bad_input_deep.py pins the messages.

Measured on the shared 2-core machine (2026-12-03, one run each, load about 4), before -> after:

- pddl check, ``and`` nested 10^5 deep: exit 3 (RecursionError) -> exit 2, 0.3 s, 101 MB;
- pddl check, a type chain 20 000 deep: past 70 s -> exit 2, 0.4 s, 61 MB (plan: 0.3 s, 33 MB);
- shell, 100 000 objects on one line: past 150 s -> 0.3 s, 45 MB;
- validate, a 3-ary at-most-once over 300 objects (27 million instances): a traceback after 61 s,
  459 MB and rising -> exit 2, 1.3 s, 129 MB; over 58 objects (195 112, under the limit): valid, 4.0 s,
  206 MB;
- a flat goal of 20 000 atoms over 20 000 objects: "reading took more than 60 s" -> pddl check 0.4 s,
  65 MB; validate of a 20 000-step plan 2.1 s, 179 MB (the planner itself then runs to its --timeout);
- the same goal against a 1-step plan (19 999 violations, each placed): past 120 s -> 2.2 s;
- 20 000 unknown names among 20 000 objects: stopped by the checking budget after 60 s -> 1.0 s;
- the shell's ``validate (push (push ...`` 10^5 deep: a RecursionError traceback -> an error line.

    .venv/bin/python benchmarks/bench_deep_inputs.py [--only NAME]
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOMAIN = (ROOT / "pddl" / "domain.pddl").read_text()
MEMORY_BYTES = 4_000_000_000
TIMEOUT_S = 150


def problem(goal: str, objects: str = "a - block", constraints: str = "", domain: str = "vsl-sp") -> str:
    section = f" (:constraints {constraints})" if constraints else ""
    return f"(define (problem p) (:domain {domain}) (:objects {objects}) (:init) (:goal {goal}){section})\n"


def chain(depth: int) -> str:
    types = " ".join(f"t{i} - t{i + 1}" for i in range(depth - 1)) + f" t{depth - 1}"
    return (
        f"(define (domain chain) (:requirements :strips :typing :negative-preconditions) (:types {types})\n"
        " (:predicates (p ?x - t0)) (:action a :parameters (?x - t0) :precondition (p ?x) :effect (not (p ?x))))\n"
    )


TRI = (
    "(define (domain tri) (:requirements :strips :typing :constraints) (:types obj)"
    " (:predicates (r ?a ?b ?c - obj) (s))"
    " (:action act :parameters (?a ?b ?c - obj) :precondition (s) :effect (r ?a ?b ?c)))\n"
)


def tri_problem(count: int) -> str:
    objects = " ".join(f"o{i}" for i in range(count))
    return (
        f"(define (problem p) (:domain tri) (:objects {objects} - obj) (:init (s)) (:goal (r o0 o1 o2))"
        " (:constraints (forall (?a ?b ?c - obj) (at-most-once (r ?a ?b ?c)))))\n"
    )


def flat(count: int) -> str:
    objects = " ".join(f"o{i}" for i in range(count)) + " - block"
    return problem("(and " + " ".join(f"(far o{i})" for i in range(count)) + ")", objects)


def nested(levels: int) -> str:
    return "(and " * levels + "(far a)" + ")" * levels


def cases() -> dict[str, tuple[dict[str, str], list[str], str | None]]:
    """name -> (files to write, the command's arguments, its standard input)."""
    chain_problem = "(define (problem q) (:domain chain) (:objects x - t0) (:init (p x)) (:goal (not (p x))))\n"
    objects = " ".join(f"o{i}" for i in range(100_000))
    check, plan = ["pddl", "check", "d.pddl", "p.pddl"], ["plan", "d.pddl", "p.pddl"]
    chain_plan = ["plan", "c.pddl", "q.pddl"]
    return {
        "check: and nested 10^5 deep": (
            {"p.pddl": problem(nested(100_000))},
            check,
            None,
        ),
        "check: and nested 997 deep (limit)": (
            {"p.pddl": problem(nested(997))},
            check,
            None,
        ),
        "plan: and nested 10^5 deep": ({"p.pddl": problem(nested(100_000))}, plan, None),
        "shell: and nested 10^5 deep": ({"p.pddl": problem(nested(100_000))}, ["shell", "d.pddl", "p.pddl"], ""),
        "check: type chain 20000": ({"c.pddl": chain(20_000)}, ["pddl", "check", "c.pddl"], None),
        "check: type chain 1000 (limit)": ({"c.pddl": chain(1000)}, ["pddl", "check", "c.pddl"], None),
        "plan: type chain 20000": (
            {"c.pddl": chain(20_000), "q.pddl": chain_problem},
            chain_plan,
            None,
        ),
        "plan: type chain 500 (limit)": (
            {"c.pddl": chain(500), "q.pddl": chain_problem},
            chain_plan,
            None,
        ),
        "shell: 100000 objects on one line": ({}, ["shell"], f"type block\nobjects {objects} - block\nquit\n"),
        "validate: at-most-once 300^3": (
            {"t.pddl": TRI, "p.pddl": tri_problem(300), "plan.txt": "(act o0 o1 o2)\n"},
            ["validate", "t.pddl", "p.pddl", "plan.txt"],
            None,
        ),
        "validate: at-most-once 58^3 (limit)": (
            {"t.pddl": TRI, "p.pddl": tri_problem(58), "plan.txt": "(act o0 o1 o2)\n"},
            ["validate", "t.pddl", "p.pddl", "plan.txt"],
            None,
        ),
        "check: flat goal 20000": ({"p.pddl": flat(20_000)}, check, None),
        "validate: flat goal 20000, 20000 steps": (
            {"p.pddl": flat(20_000), "plan.txt": "".join(f"(push o{i})\n" for i in range(20_000))},
            ["validate", "d.pddl", "p.pddl", "plan.txt"],
            None,
        ),
        "validate: flat goal 20000, 1 step": (
            {"p.pddl": flat(20_000), "plan.txt": "(push o0)\n"},
            ["validate", "d.pddl", "p.pddl", "plan.txt"],
            None,
        ),
        "check: 20000 unknown names among 20000": (
            {"p.pddl": flat(20_000).replace("(far o", "(far x")},
            check,
            None,
        ),
        "shell: validate (push (push ... 10^5 deep": (
            {},
            ["shell", "d.pddl"],
            "objects a - block\nvalidate " + "(push " * 100_000 + "a" + ")" * 100_000 + "\nquit\n",
        ),
        "check: objects and, or, not": (
            {"p.pddl": problem("(far a)", "a and or not - block")},
            check,
            None,
        ),
        "plan: another domain": ({"p.pddl": problem("(far a)", domain="blocks")}, ["plan", "d.pddl", "p.pddl"], None),
        "plan: --conflict-budget nan": ({}, ["plan", "d.pddl", "x.pddl", "--conflict-budget", "nan"], None),
        "plan: --conflict-budget 1e300": ({}, ["plan", "d.pddl", "x.pddl", "--conflict-budget", "1e300"], None),
    }


def limit_memory() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_BYTES, resource.RLIM_INFINITY))


def measure(folder: Path, arguments: list[str], stdin: str | None) -> tuple[int, float, float, str]:
    """(exit code, wall-clock s, peak RSS MB, first line of stderr or stdout) of one run; the streams go
    to files and the process is reaped with ``wait4``, whose resource usage is that process's alone."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
    (folder / "stdin.txt").write_text(stdin or "")
    with (
        open(folder / "stdin.txt") as given,
        open(folder / "out.txt", "w") as out,
        open(folder / "err.txt", "w") as err,
    ):
        start = time.perf_counter()
        process = subprocess.Popen(
            [sys.executable, "-m", "vslsp", *arguments],
            cwd=folder,
            env=env,
            stdin=given,
            stdout=out,
            stderr=err,
            preexec_fn=limit_memory,
        )
        while True:
            pid, status, usage = os.wait4(process.pid, os.WNOHANG)
            if pid:
                break
            if time.perf_counter() - start > TIMEOUT_S:
                process.kill()
            time.sleep(0.01)
        wall = time.perf_counter() - start
    process.returncode = os.waitstatus_to_exitcode(status)
    errors = [line for line in (folder / "err.txt").read_text().splitlines() if line.lower().startswith("error")]
    said = [line for line in (folder / "out.txt").read_text().splitlines() if ": error: " in line]
    lines = said or errors or (folder / "out.txt").read_text().splitlines() or [""]
    return process.returncode, wall, usage.ru_maxrss / 1024, lines[0][:110]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", help="run the cases whose name contains this")
    args = parser.parse_args()
    print(f"{'case':42} {'exit':>4} {'s':>6} {'peak MB':>8}  message")
    for name, (files, arguments, stdin) in cases().items():
        if args.only and args.only not in name:
            continue
        with tempfile.TemporaryDirectory(prefix="vslsp-deep-") as folder:
            Path(folder, "d.pddl").write_text(DOMAIN)
            for file, text in files.items():
                Path(folder, file).write_text(text)
            code, wall, peak, message = measure(Path(folder), arguments, stdin)
        print(f"{name:42} {code:>4} {wall:6.1f} {peak:8.0f}  {message}", flush=True)


if __name__ == "__main__":
    main()
