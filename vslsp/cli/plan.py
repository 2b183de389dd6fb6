"""``vslsp plan DOMAIN PROBLEM``: plan with Fast Downward (PDDL 3.0 constraints compiled into the lifted domain)."""

from __future__ import annotations

import json
import os
from pathlib import Path

import click

from vslsp.cli.pddl import debug_option, pddl_edge
from vslsp.errors import InputError


def writable_file(path: str) -> Path:
    """``path``'s folder created and probed for writing, before any work; InputError if it cannot be written."""
    target = Path(path)
    if target.is_dir():
        raise InputError(f"--out {path}: is a folder; give a file name such as {Path(path) / 'plan.txt'}")
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        existed = target.exists()
        with open(target, "a"):
            pass
        if not existed:
            os.remove(target)
    except OSError as error:
        raise InputError(f"--out {path}: cannot write there ({error.strerror}); choose a writable folder") from None
    return target


@click.command()
@click.argument("domain", type=click.Path(dir_okay=False))
@click.argument("problem", type=click.Path(dir_okay=False))
@click.option(
    "--planner",
    default="fast-downward",
    show_default=True,
    help="fast-downward (greedy FF), fast-downward-lama, fast-downward-opt (A* LM-cut), or any installed "
    "unified-planning oneshot planner.",
)
@click.option(
    "--compilation",
    type=click.Choice(["lifted", "ground"]),
    default=None,
    help="How PDDL 3.0 constraints are compiled away: lifted (default with Fast Downward: monitors in the "
    "action schemas) or ground (unified-planning's TrajectoryConstraintsRemover).",
)
@click.option(
    "--timeout", type=click.FloatRange(min=0.1), default=None, help="Give up after this many seconds (exit 1)."
)
@click.option(
    "--out",
    type=click.Path(dir_okay=False),
    default=None,
    help="Also write the plan there, one (action arg ...) per line (the PLAN of vslsp validate).",
)
@click.option(
    "--json",
    "as_json",
    is_flag=True,
    help='Print {"plan": [...] or null, "planner": str, "time_s": float, "compilation": str, "warnings": '
    '[...]} (and "error" on failure).',
)
@debug_option
def plan(
    domain: str,
    problem: str,
    planner: str,
    compilation: str | None,
    timeout: float | None,
    out: str | None,
    as_json: bool,
    debug: bool,
) -> None:
    """Find a plan for PROBLEM in DOMAIN, keeping its PDDL 3.0 trajectory constraints.

    Exit 0: a plan; 1: no plan; 2: bad input; 3: the planner or compiler failed inside.
    """
    from vslsp.symbolic import Compilation, check_planner, read_pddl, save, solve

    with pddl_edge(as_json, debug, {"plan": None, "planner": planner}) as warned:
        check_planner(planner)
        target = writable_file(out) if out else None
        parsed_domain, parsed_problem = read_pddl(domain, problem)
        assert parsed_problem is not None
        result = solve(
            parsed_domain,
            parsed_problem,
            planner=planner,
            compilation=Compilation(compilation) if compilation else None,
            timeout=timeout,
        )
        if target is not None:
            save(result.to_pddl(), target)
    if as_json:
        click.echo(json.dumps({**result.to_dict(), "warnings": warned}))
        return
    for number, line in enumerate(result.lines(), start=1):
        click.echo(f"{number}. {line}")
    steps = len(result.steps)
    click.echo(
        f"{steps} step{'' if steps == 1 else 's'}, {result.planner}, constraints compiled: "
        f"{result.compilation.value}, {result.time_s:.2f} s",
        err=True,
    )
