"""``vslsp validate DOMAIN PROBLEM PLAN``: simulate a plan, check its goal and PDDL 3.0 constraints."""

from __future__ import annotations

import json

import click

from vslsp.errors import TaskFailed


@click.command()
@click.argument("domain", type=click.Path(dir_okay=False))
@click.argument("problem", type=click.Path(dir_okay=False))
@click.argument("plan", type=click.Path(dir_okay=False))
@click.option("--json", "as_json", is_flag=True, help='Print {"valid": bool, "reason": str}.')
def validate(domain: str, problem: str, plan: str, as_json: bool) -> None:
    """Check PLAN (one "(action arg ...)" per line) against DOMAIN and PROBLEM (exit 1: invalid)."""
    from vslsp.symbolic import read_pddl, read_plan
    from vslsp.symbolic import validate as validate_plan

    parsed_domain, parsed_problem = read_pddl(domain, problem)
    assert parsed_problem is not None
    verdict = validate_plan(parsed_domain, parsed_problem, read_plan(plan, parsed_domain, parsed_problem))
    if as_json:
        click.echo(json.dumps(verdict.to_dict()))
    else:
        click.echo(f"{'valid' if verdict.valid else 'invalid'}: {verdict.reason}")
    if not verdict.valid:
        raise TaskFailed(f"invalid plan: {verdict.reason}")
