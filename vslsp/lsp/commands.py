"""The server's commands ``vslsp.plan`` and ``vslsp.validate``: the JSON of ``vslsp plan --json`` and
``vslsp validate --json`` (docs/cli.md), computed by the same functions on the editor's text.

Both are blocking (the planner runs for seconds): the server calls them off its event loop, one at
a time (the PDDL warnings are collected process-wide). Their arguments name the files (URIs or paths;
a problem's domain is found as for diagnostics; none: the problem and plan last opened or edited), and
the editor's text is used, saved or not. The user is also told the outcome (``window/showMessage``),
as an editor bound to a key shows nothing of a command's result.
"""

from __future__ import annotations

import logging
import os
import threading
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from lsprotocol import types

from vslsp.errors import VslspError
from vslsp.lsp.workspace import Files, path_of, uri_of

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


def named(arguments: tuple[Any, ...], names: tuple[str, ...], last: dict[str, str]) -> dict[str, Any]:
    """A command's arguments by name: one object, or the files in order (the domain may be left out);
    with none, the problem and plan last opened or edited (``last``: kind -> URI)."""
    if len(arguments) == 1 and isinstance(arguments[0], dict):
        return dict(arguments[0])
    if not arguments:
        return {name: last[name] for name in names if name in last}
    files = [str(a) for a in arguments]
    return dict(zip(names[len(names) - len(files) :] if len(files) < len(names) else names, files))


def sources(
    files: Files, given: dict[str, Any], names: tuple[str, ...], failure: dict[str, Any]
) -> tuple[dict[str, Source], dict[str, Any]]:
    """The editor's text of each named file (the problem's domain found when not given), or else the
    CLI's failure object (exit code 2) saying what is missing."""

    def fail(message: str) -> tuple[dict[str, Source], dict[str, Any]]:
        return {}, {**failure, "error": message, "exit_code": 2, "warnings": []}

    uris = {name: as_uri(str(given[name])) for name in names if given.get(name)}
    if "problem" not in uris:
        return fail(f"give the problem: arguments {list(names)} as URIs or paths, or one object with those keys")
    if "plan" in names and "plan" not in uris:
        return fail("give the plan to validate (a .plan file, one (action arg ...) per line)")
    if "domain" not in uris:
        domain = files.domain_for(uris["problem"])
        if domain is None:
            header = files.header(uris["problem"])
            return fail(
                f"{path_of(uris['problem'])}: no domain '{header.domain}' among the open documents and the "
                ".pddl files of its folder; give the domain too"
            )
        uris["domain"] = domain
    sources: dict[str, Source] = {}
    for name in names:
        text = files.text(uris[name])
        if text is None:
            return fail(f"{path_of(uris[name])}: cannot read the file (not open in the editor, not on disk)")
        sources[name] = Source(path_of(uris[name]), text)
    return sources, {}


def as_uri(given: str) -> str:
    return given if "://" in given or given.startswith("file:") else uri_of(os.path.abspath(given))


def told(command: str, result: dict[str, Any]) -> types.ShowMessageParams:
    """What the user is shown of a command's result: the plan or the verdict, or the error."""
    if "error" in result:
        kind = types.MessageType.Error if result.get("exit_code") != 1 else types.MessageType.Warning
        return types.ShowMessageParams(kind, f"{command}: {result['error']}")
    if command.endswith("plan"):
        steps = result["plan"]
        listed = "; ".join(f"{n}. {step}" for n, step in enumerate(steps, 1))
        count = f"{len(steps)} step{'' if len(steps) == 1 else 's'}"
        said = f"{count} ({result['planner']}, {result['time_s']:.2f} s): {listed}"
        return types.ShowMessageParams(types.MessageType.Info, f"{command}: {said}")
    kind = types.MessageType.Info if result["valid"] else types.MessageType.Warning
    return types.ShowMessageParams(kind, f"{command}: {'valid' if result['valid'] else 'invalid'}: {result['reason']}")


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
