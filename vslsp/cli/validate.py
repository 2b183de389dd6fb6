"""``vslsp validate DOMAIN PROBLEM PLAN``: simulate a plan, check its goal and PDDL 3.0 constraints."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import click

from vslsp.cli.pddl import debug_option, max_size_option, pddl_edge


@click.command()
@click.argument("domain", type=click.Path(dir_okay=False))
@click.argument("problem", type=click.Path(dir_okay=False))
@click.argument("plan", type=click.Path(dir_okay=False))
@click.option(
    "--json",
    "as_json",
    is_flag=True,
    help='Print {"valid": bool, "reason": str, "violations": [{"kind", "text", "step", "file", "line", '
    '"column", "message"}], "warnings": [...]}.',
)
@max_size_option
@debug_option
def validate(domain: str, problem: str, plan: str, as_json: bool, max_bytes: int, debug: bool) -> None:
    """Check PLAN against DOMAIN and PROBLEM (exit 1: invalid).

    PLAN has one step per line: "(action arg ...)", "0: (action arg ...)" as VAL and IPC planners
    write it, or "1. action arg ..." as vslsp plan prints it; for a temporal problem
    "T: (action arg ...) [D]" (start time T, duration D).

    An invalid plan lists every violation with its FILE:LINE:COL: the first step that cannot be
    applied (in PLAN) with its false preconditions, each goal conjunct that does not hold at the
    end and each broken constraint (in PROBLEM), with the step where it broke.
    """
    from vslsp.cli import pddl21

    if pddl21.beyond_strips(domain, max_bytes, as_json, debug):
        pddl21.validate(domain, problem, plan, as_json, max_bytes, debug)
        return
    from vslsp.symbolic import read_pddl, read_plan
    from vslsp.symbolic import validate as validate_plan
    from vslsp.symbolic.io.locate import where
    from vslsp.symbolic.io.pddl import read_text

    with pddl_edge(as_json, debug, {"valid": None}) as warned:
        parsed_domain, parsed_problem = read_pddl(domain, problem, max_bytes)
        assert parsed_problem is not None
        verdict = validate_plan(parsed_domain, parsed_problem, read_plan(plan, parsed_domain, parsed_problem))
        texts = (
            (read_text(problem, max_bytes=max_bytes), Path(plan).read_bytes().decode("utf-8-sig"))
            if not verdict.valid
            else ("", "")
        )
        violations = verdict.located(texts[0], problem, texts[1], plan)
    if as_json:
        click.echo(json.dumps({**verdict.to_dict(), "violations": violations, "warnings": warned}))
    else:
        click.echo(f"{'valid' if verdict.valid else 'invalid'}: {verdict.reason}")
        for violation in violations:
            click.echo(f"  {where(violation)}: {violation['message']}")
    if not verdict.valid:
        sys.exit(1)  # the verdict is printed: exit 1 without a second message
