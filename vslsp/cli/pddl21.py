"""``vslsp plan``, ``vslsp validate`` and ``vslsp pddl check`` on numeric and temporal PDDL
(:mod:`vslsp.symbolic.engines.pddl21`): the commands hand a domain beyond STRIPS to these functions."""

from __future__ import annotations

import json
import sys

import click

from vslsp.cli.pddl import pddl_edge


def beyond_strips(domain: str, max_bytes: int, as_json: bool, debug: bool) -> bool:
    """Whether DOMAIN is numeric, temporal or has derived predicates (its reading errors at the edge)."""
    from vslsp.symbolic.engines.pddl21 import domain_is_beyond_strips

    with pddl_edge(as_json, debug, {}):
        return domain_is_beyond_strips(domain, max_bytes)


def plan(
    domain: str,
    problem: str,
    planner: str | None,
    timeout: float,
    memory: int,
    out: str | None,
    as_json: bool,
    max_bytes: int,
    debug: bool,
) -> None:
    """Plan with a unified-planning engine for the problem's kind (``planner`` None: the automatic one)."""
    from vslsp.cli.params import prepare_output_file
    from vslsp.interrupts import memory_limit_mb
    from vslsp.outputs import refuse_input
    from vslsp.symbolic.engines import pddl21
    from vslsp.symbolic.io.pddl import save

    with pddl_edge(as_json, debug, {"plan": None, "planner": planner}) as warned:
        target = prepare_output_file(out) if out is not None else None
        if target is not None:
            refuse_input(target, {"domain": domain, "problem": problem}, "--out")
        read = pddl21.read(domain, problem, max_bytes)
        result = pddl21.solve(read, planner, timeout, memory_limit_mb(memory))
        if target is not None:
            save(result.to_pddl(), target)
    if as_json:
        click.echo(json.dumps({**result.to_dict(), "warnings": warned}))
        return
    for number, line in enumerate(result.lines(), start=1):
        click.echo(f"{number}. {line}")
    steps = len(result.steps)
    makespan = f", makespan {result.makespan:g}" if result.makespan is not None else ""
    click.echo(
        f"{steps} step{'' if steps == 1 else 's'}, {result.planner} ({read.kind_name}){makespan}, "
        f"{result.time_s:.2f} s",
        err=True,
    )


def validate(domain: str, problem: str, plan: str, as_json: bool, max_bytes: int, debug: bool) -> None:
    """Check PLAN (sequential, or time-triggered for a temporal problem); exit 1 when invalid."""
    from vslsp.symbolic.engines import pddl21
    from vslsp.symbolic.io.locate import where
    from vslsp.symbolic.language.files import read_text
    from vslsp.symbolic.validation.pddl21 import read_plan
    from vslsp.symbolic.validation.pddl21 import validate as validate_plan

    with pddl_edge(as_json, debug, {"valid": None}) as warned:
        read = pddl21.read(domain, problem, max_bytes)
        steps = read_plan(read_text(plan, "plan file", max_bytes=max_bytes), plan, read.temporal)
        verdict = validate_plan(read, steps, plan, problem)
    if as_json:
        click.echo(json.dumps({**verdict.to_dict(), "warnings": warned}))
    else:
        metric = f" (metric {verdict.metric:g})" if verdict.metric is not None else ""
        click.echo(f"{'valid' if verdict.valid else 'invalid'}: {verdict.reason}{metric}")
        for violation in verdict.violations:
            at = f"step {violation['step']}" if violation["step"] else ""
            at += f" at time {violation['time']:g}" if violation["time"] is not None else ""
            click.echo(f"  {where(violation)}: {at + ': ' if at else ''}{violation['message']}")
    if not verdict.valid:
        sys.exit(1)
