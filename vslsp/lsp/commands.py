"""The server's commands ``vslsp.plan`` and ``vslsp.validate``: the JSON of ``vslsp plan --json`` and
``vslsp validate --json`` (docs/cli.md), computed by the same functions on the editor's text.

Both are blocking (the planner runs for seconds): the server calls them off its event loop, one at
a time (the PDDL warnings are collected process-wide).
"""

from __future__ import annotations

import logging
import threading
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from vslsp.errors import VslspError

logger = logging.getLogger(__name__)
_ONE_AT_A_TIME = threading.Lock()


@dataclass(frozen=True)
class Source:
    """A file's text as the editor holds it; ``name`` is its path (what messages call it)."""

    name: str
    text: str


def plan_json(
    domain: Source,
    problem: Source,
    planner: str = "fast-downward",
    compilation: str | None = None,
    timeout: float | None = None,
) -> dict[str, Any]:
    """``vslsp plan DOMAIN PROBLEM --json``'s object: ``{"plan", "planner", "time_s", "compilation",
    "warnings"}``, or ``{"plan": null, "planner", "error", "exit_code", "warnings"}``."""
    from vslsp.symbolic import Compilation, check_planner, parse_pddl, solve

    def run() -> dict[str, Any]:
        check_planner(planner)
        parsed_domain, parsed_problem = parse_pddl(
            domain.text, problem.text, domain_name=domain.name, problem_name=problem.name
        )
        assert parsed_problem is not None
        chosen = None
        if compilation is not None:
            try:
                chosen = Compilation(compilation)
            except ValueError:
                from vslsp.errors import InputError

                raise InputError(f"compilation {compilation!r}: choose lifted or ground") from None
        return solve(parsed_domain, parsed_problem, planner=planner, compilation=chosen, timeout=timeout).to_dict()

    return _as_cli(run, {"plan": None, "planner": planner})


def validate_json(domain: Source, problem: Source, plan: Source) -> dict[str, Any]:
    """``vslsp validate DOMAIN PROBLEM PLAN --json``'s object: ``{"valid", "reason", "warnings"}``, or
    ``{"valid": null, "error", "exit_code", "warnings"}``."""
    from vslsp.symbolic import parse_pddl, parse_plan, validate

    def run() -> dict[str, Any]:
        parsed_domain, parsed_problem = parse_pddl(
            domain.text, problem.text, domain_name=domain.name, problem_name=problem.name
        )
        assert parsed_problem is not None
        steps = parse_plan(plan.text, parsed_domain, parsed_problem, plan.name)
        return validate(parsed_domain, parsed_problem, steps).to_dict()

    return _as_cli(run, {"valid": None})


def _as_cli(run: Callable[[], dict[str, Any]], failure: dict[str, Any]) -> dict[str, Any]:
    """``run()`` plus its warnings, or ``failure`` with the error as the CLI's edge words it."""
    from vslsp.symbolic import InternalError, PddlWarning

    with _ONE_AT_A_TIME, warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", PddlWarning)
        try:
            result = run()
        except VslspError as error:
            result = {**failure, "error": str(error), "exit_code": error.exit_code}
        except Exception as error:  # a bug or a failure we did not foresee: not the user's input
            logger.exception("internal error")  # the traceback goes to the server's log (stderr)
            wrapped = InternalError(
                f"internal error ({type(error).__name__}: {error}); run with --debug for the traceback"
            )
            result = {**failure, "error": str(wrapped), "exit_code": wrapped.exit_code}
    return {**result, "warnings": [str(w.message) for w in caught if issubclass(w.category, PddlWarning)]}
