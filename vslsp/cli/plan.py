"""``vslsp plan DOMAIN PROBLEM``: plan with Fast Downward (PDDL 3.0 constraints compiled into the lifted domain)."""

from __future__ import annotations

import json
from typing import TYPE_CHECKING

import click

from vslsp.cli.params import int_range, non_negative_float, positive_float, prepare_output_file
from vslsp.cli.pddl import debug_option, max_size_option, pddl_edge
from vslsp.symbolic.engines.planner import DEFAULT_MEMORY_MB, DEFAULT_TIMEOUT_S

MAX_TIMEOUT_S = 7 * 24 * 3600.0  # a week
MAX_MEMORY_MB = 1024 * 1024  # a terabyte

if TYPE_CHECKING:
    from vslsp.symbolic import Domain, Problem


@click.command()
@click.argument("domain", type=click.Path(dir_okay=False))
@click.argument("problem", type=click.Path(dir_okay=False))
@click.option(
    "--planner",
    default="fast-downward",
    show_default=True,
    help="fast-downward (greedy FF), fast-downward-lama, fast-downward-opt (A* LM-cut), or any installed "
    "unified-planning oneshot planner. Numeric and temporal domains: enhsp, tamer or aries (default: chosen "
    "by the problem's kind, docs/planning.md).",
)
@click.option(
    "--compilation",
    type=click.Choice(["lifted", "ground"]),
    default=None,
    help="How PDDL 3.0 constraints are compiled away: lifted (default with Fast Downward: monitors in the "
    "action schemas) or ground (unified-planning's TrajectoryConstraintsRemover).",
)
@click.option(
    "--timeout",
    type=positive_float(MAX_TIMEOUT_S),
    default=DEFAULT_TIMEOUT_S,
    show_default=True,
    help='The planner\'s time limit in wall-clock seconds; reaching it is exit 1 ("time limit of N s reached").',
)
@click.option(
    "--memory",
    type=int_range(64, MAX_MEMORY_MB),
    default=DEFAULT_MEMORY_MB,
    show_default=True,
    help="The planner's memory limit in MB (address space of each of its processes); reaching it is exit 1.",
)
@click.option(
    "--out",
    type=click.Path(dir_okay=False),
    default=None,
    help="Also write the plan there, one (action arg ...) per line (the PLAN of vslsp validate).",
)
@click.option(
    "--conflict-budget",
    type=non_negative_float(MAX_TIMEOUT_S),
    default=30.0,
    show_default=True,
    help="When the problem is proved unsolvable, spend at most this many seconds finding a minimal set of "
    "goal conjuncts and constraints that conflict (0: do not search).",
)
@click.option(
    "--json",
    "as_json",
    is_flag=True,
    help='Print {"plan": [...] or null, "planner": str, "time_s": float, "compilation": str, "warnings": '
    '[...]} (and "error", "conflict", "conflict_minimal" on failure).',
)
@max_size_option
@debug_option
def plan(
    domain: str,
    problem: str,
    planner: str,
    compilation: str | None,
    timeout: float,
    memory: int,
    out: str | None,
    conflict_budget: float,
    as_json: bool,
    max_bytes: int,
    debug: bool,
) -> None:
    """Find a plan for PROBLEM in DOMAIN, keeping its PDDL 3.0 trajectory constraints.

    When the planner proves that no plan exists, names a minimal set of goal conjuncts and
    constraints that cannot all hold (FILE:LINE:COL each).

    Exit 0: a plan; 1: no plan (or a time or memory limit reached); 2: bad input; 3: the
    planner or compiler failed inside.
    """
    from vslsp.cli import pddl21
    from vslsp.outputs import refuse_input
    from vslsp.symbolic import Compilation, Unsolvable, check_planner, read_pddl, save, solve

    if pddl21.beyond_strips(domain, max_bytes, as_json, debug):
        named = click.get_current_context().get_parameter_source("planner") is not click.core.ParameterSource.DEFAULT
        pddl21.plan(domain, problem, planner if named else None, timeout, memory, out, as_json, max_bytes, debug)
        return
    failure: dict = {"plan": None, "planner": planner, "conflict": None, "conflict_minimal": None}
    with pddl_edge(as_json, debug, failure) as warned:
        check_planner(planner)
        target = prepare_output_file(out) if out is not None else None
        if target is not None:
            refuse_input(target, {"domain": domain, "problem": problem}, "--out")
        parsed_domain, parsed_problem = read_pddl(domain, problem, max_bytes)
        assert parsed_problem is not None
        try:
            result = solve(
                parsed_domain,
                parsed_problem,
                planner=planner,
                compilation=Compilation(compilation) if compilation else None,
                timeout=timeout,
                memory_mb=memory,
            )
        except Unsolvable as error:
            if not conflict_budget:
                raise
            lines = _explained(
                parsed_domain, parsed_problem, problem, planner, conflict_budget, memory, failure, max_bytes
            )
            if as_json:
                raise
            raise Unsolvable("\n".join([error.reason, *lines])) from None
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


def _explained(
    domain: Domain,
    problem: Problem,
    path: str,
    planner: str,
    budget: float,
    memory: int,
    failure: dict,
    max_bytes: int,
) -> list[str]:
    """The conflict of an unsolvable problem as lines of text; ``failure`` gets its JSON fields."""
    from vslsp.errors import VslspError
    from vslsp.symbolic.io.locate import where
    from vslsp.symbolic.io.pddl import read_text
    from vslsp.symbolic.validation.conflict import explain

    try:
        conflict = explain(domain, problem, planner=planner, budget_s=budget, memory_mb=memory, known_unsolvable=True)
    except VslspError as error:  # the plan's own verdict stands; the explanation is extra
        return [f"why: not found ({error})"]
    assert conflict is not None
    items = conflict.located(read_text(path, max_bytes=max_bytes), path)
    reasons = conflict.reasons(domain, problem)
    failure["conflict"], failure["conflict_minimal"], failure["reasons"] = items, conflict.minimal, reasons
    lines = [f"why: {conflict.summary()}", *(f"  {where(i)}: {i['kind']} {i['text']}" for i in items)]
    return lines + [f"  because: {reason}" for reason in reasons]
