"""``vslsp plan DOMAIN PROBLEM``: plan with unified-planning (Fast Downward by default)."""

from __future__ import annotations

import json

import click


@click.command()
@click.argument("domain", type=click.Path(dir_okay=False))
@click.argument("problem", type=click.Path(dir_okay=False))
@click.option("--planner", default="fast-downward", show_default=True,
              help="fast-downward (greedy FF), fast-downward-lama, fast-downward-opt (A* LM-cut), or any installed unified-planning oneshot planner.")
@click.option("--out", type=click.Path(dir_okay=False), default=None,
              help="Also write the plan there, one (action arg ...) per line (the PLAN of vslsp validate).")
@click.option("--json", "as_json", is_flag=True, help='Print {"plan": [...], "planner": str, "time_s": float}.')
def plan(domain: str, problem: str, planner: str, out: str | None, as_json: bool) -> None:
    """Find a plan for PROBLEM in DOMAIN, keeping its PDDL 3.0 trajectory constraints (exit 1: no plan)."""
    from vslsp.symbolic import read_pddl, save, solve

    parsed_domain, parsed_problem = read_pddl(domain, problem)
    assert parsed_problem is not None
    result = solve(parsed_domain, parsed_problem, planner=planner)
    if out:
        save(result.to_pddl(), out)
    if as_json:
        click.echo(json.dumps(result.to_dict()))
        return
    for number, line in enumerate(result.lines(), start=1):
        click.echo(f"{number}. {line}")
    click.echo(f"{len(result.steps)} step(s), {result.planner}, {result.time_s:.2f} s", err=True)
