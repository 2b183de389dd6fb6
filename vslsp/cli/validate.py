"""``vslsp validate DOMAIN PROBLEM PLAN``: simulate a plan, check its goal and PDDL 3.0 constraints."""

from __future__ import annotations

import json
import sys

import click

from vslsp.cli.pddl import debug_option, pddl_edge


@click.command()
@click.argument("domain", type=click.Path(dir_okay=False))
@click.argument("problem", type=click.Path(dir_okay=False))
@click.argument("plan", type=click.Path(dir_okay=False))
@click.option("--json", "as_json", is_flag=True, help='Print {"valid": bool, "reason": str, "warnings": [...]}.')
@debug_option
def validate(domain: str, problem: str, plan: str, as_json: bool, debug: bool) -> None:
    """Check PLAN against DOMAIN and PROBLEM (exit 1: invalid).

    PLAN has one step per line: "(action arg ...)", "0: (action arg ...)" as VAL and IPC planners
    write it, or "1. action arg ..." as vslsp plan prints it.
    """
    from vslsp.symbolic import read_pddl, read_plan
    from vslsp.symbolic import validate as validate_plan

    with pddl_edge(as_json, debug, {"valid": None}) as warned:
        parsed_domain, parsed_problem = read_pddl(domain, problem)
        assert parsed_problem is not None
        verdict = validate_plan(parsed_domain, parsed_problem, read_plan(plan, parsed_domain, parsed_problem))
    if as_json:
        click.echo(json.dumps({**verdict.to_dict(), "warnings": warned}))
    else:
        click.echo(f"{'valid' if verdict.valid else 'invalid'}: {verdict.reason}")
    if not verdict.valid:
        sys.exit(1)  # the verdict is printed: exit 1 without a second message
