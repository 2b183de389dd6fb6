"""Cold cost of `vslsp plan` and `vslsp validate` against `vslsp pddl check` (issue 45, item 5: plan
and validate within 1.5x check plus the planner's own time).

Each command runs as a user runs it (a fresh ``python -m vslsp`` process) on the shipped domain and
pull-in-order problem; its wall time and CPU time (its own and its children's: Fast Downward's
translator and search) are measured from outside. The planner's own time is what `plan --json`
reports (``time_s``: Fast Downward, from the texts to the plan). The reference, measured in the same
run: `vslsp pddl check` on the same files. Each figure is the minimum over ``--runs`` (the machine may
be shared: the minimum is the run least disturbed).

    .venv/bin/python benchmarks/bench_cold.py [--runs 5] [--json results.json]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
DOMAIN, PROBLEM = REPO / "pddl" / "domain.pddl", REPO / "pddl" / "pull-in-order.pddl"


def timed(*args: str) -> tuple[float, float, str]:
    """(wall s, CPU s of the process and its children, stdout) of ``python -m vslsp ARGS``."""
    before = os.times()
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "vslsp", *args], capture_output=True, text=True, check=False)
    wall = time.perf_counter() - start
    after = os.times()
    if done.returncode != 0:
        raise SystemExit(f"vslsp {' '.join(args)} failed: {done.stderr.strip()}")
    return (
        wall,
        (after.children_user - before.children_user) + (after.children_system - before.children_system),
        done.stdout,
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        plan_file = Path(folder) / "plan.txt"
        commands = {
            "check": ["pddl", "check", str(DOMAIN), str(PROBLEM)],
            "plan": ["plan", str(DOMAIN), str(PROBLEM), "--json", "--out", str(plan_file)],
            "validate": ["validate", str(DOMAIN), str(PROBLEM), str(plan_file)],
        }
        found: dict[str, dict[str, float]] = {}
        planner_s = float("inf")
        for name, command in commands.items():
            walls, cpus = [], []
            for _ in range(args.runs):
                wall, cpu, out = timed(*command)
                walls.append(wall)
                cpus.append(cpu)
                if name == "plan":
                    planner_s = min(planner_s, float(json.loads(out)["time_s"]))
            found[name] = {"wall_s": min(walls), "cpu_s": min(cpus)}
    check = found["check"]
    print(f"min of {args.runs} runs, shipped domain + pull-in-order (cold processes)")
    for name, figures in found.items():
        print(f"  {name:<9} wall {figures['wall_s']:.2f} s   cpu {figures['cpu_s']:.2f} s")
    print(f"  planner's own time (plan --json time_s): {planner_s:.2f} s")
    plan_ratio = found["plan"]["wall_s"] / (1.5 * check["wall_s"] + planner_s)
    validate_ratio = found["validate"]["wall_s"] / (1.5 * check["wall_s"])
    print(f"  plan / (1.5 x check + planner): {plan_ratio:.2f} (target <= 1)")
    print(f"  validate / (1.5 x check): {validate_ratio:.2f} (target <= 1)")
    if args.json:
        args.json.write_text(
            json.dumps({**found, "planner_s": planner_s, "plan_ratio": plan_ratio, "validate_ratio": validate_ratio})
        )


if __name__ == "__main__":
    main()
