"""``vslsp pddl check DOMAIN [PROBLEM]``: every error and warning of PDDL 3.0 files, from the language
engine (:mod:`vslsp.symbolic.language`: no unified-planning, a few Python start-ups cold).

Also the shared edge of the PDDL commands (``pddl check``, ``plan``, ``validate``): warnings
printed as ``warning: ...``, ``--json`` always JSON (``{"error": ...}`` on failure), a failure
inside a planner or compiler an internal error (exit 3) with its traceback only under ``--debug``.
"""

from __future__ import annotations

import json
import sys
import traceback
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

import click

from vslsp.errors import VslspError
from vslsp.outputs import NO_SPACE, write_error


@contextmanager
def pddl_edge(as_json: bool, debug: bool, failure: dict[str, Any] | None = None) -> Iterator[list[str]]:
    """Run a PDDL command: collects the PddlWarnings (the list yielded, printed on stderr at the end);
    on an error prints ``failure`` + ``{"error": ...}`` as JSON when ``as_json``, the traceback when ``debug``."""
    from vslsp.symbolic import InternalError, NoPlan, PddlWarning

    collected: list[str] = []
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", PddlWarning)
            try:
                yield collected
            finally:
                collected.extend(str(w.message) for w in caught if issubclass(w.category, PddlWarning))
                for message in collected:
                    click.echo(f"warning: {message}", err=True)
    except Exception as error:
        if isinstance(error, (click.exceptions.Exit, click.ClickException)):
            raise
        if isinstance(error, OSError) and error.errno in NO_SPACE:  # a full disk (the planner's folder too)
            error = write_error(error.filename or "a temporary file", error)
        if not isinstance(error, VslspError):  # a bug or a failure we did not foresee: not the user's input
            wrapped = InternalError(
                f"internal error ({type(error).__name__}: {error}); run with --debug for the traceback"
            )
            wrapped.__cause__ = error
            error = wrapped
        if debug and error.__cause__ is not None:
            traceback.print_exception(error.__cause__, file=sys.stderr)
        if as_json:
            click.echo(
                json.dumps(
                    {
                        **(failure or {}),
                        "error": str(error),
                        "exit_code": error.exit_code,
                        "warnings": collected,
                        **({"status": error.status.value} if isinstance(error, NoPlan) else {}),
                    }
                )
            )
            error.json_printed = True  # type: ignore[attr-defined]
        raise error from None


def debug_option(function: Any) -> Any:
    return click.option("--debug", is_flag=True, help="Show the traceback of an internal error (exit 3).")(function)


#: The largest ``--max-size``, in MB: past it a file's memory (about 70 bytes a byte read) outgrows a machine.
MAX_SIZE_MB = 10_000.0


def max_size_option(function: Any) -> Any:
    """``--max-size MB``: the largest PDDL file read (:data:`vslsp.symbolic.language.files.MAX_PDDL_BYTES`
    by default), given to the function as ``max_bytes``."""
    from vslsp.cli.params import millions_option
    from vslsp.symbolic.language.files import MAX_PDDL_BYTES, MAX_SIZE_OPTION

    help = "The largest PDDL file read, in MB (a larger one is exit 2, naming it and its size)."
    return millions_option(MAX_SIZE_OPTION, "max_bytes", MAX_PDDL_BYTES, "MB", MAX_SIZE_MB, help)(function)


@click.group()
def pddl() -> None:
    """Work with PDDL 3.0 domain and problem files."""


@pddl.command()
@click.argument("domain", type=click.Path(dir_okay=False))
@click.argument("problem", type=click.Path(dir_okay=False), required=False)
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object on stdout.")
@max_size_option
@debug_option
def check(domain: str, problem: str | None, as_json: bool, max_bytes: int, debug: bool) -> None:
    """Check DOMAIN (and PROBLEM): every error and warning, one line each as
    FILE:LINE:COL: error|warning: message (did you mean 'x'?). Exit 2 with any error, 0 otherwise."""
    from vslsp.symbolic.language import check_files

    with pddl_edge(as_json, debug, {"diagnostics": []}):
        analysis = check_files(domain, problem, max_bytes)
    summary = _summary(analysis, domain, problem)
    if as_json:
        report: dict[str, Any] = {
            "diagnostics": [d.to_dict() for d in analysis.diagnostics],
            "exit_code": analysis.exit_code,
            **summary,
            "warnings": [d.format() for d in analysis.warnings],
        }
        if analysis.errors:
            report["error"] = _failure(analysis)
        click.echo(json.dumps(report))
    else:
        for diagnostic in analysis.diagnostics:
            click.echo(diagnostic.format())
        if analysis.errors:
            counts = f"{_count(len(analysis.errors), 'error')}, {_count(len(analysis.warnings), 'warning')}"
            click.echo(counts, err=True)
        else:
            _print_summary(summary, domain, problem)
    if analysis.errors:
        sys.exit(2)  # the diagnostics are printed: no second message


def _failure(analysis: Any) -> str:
    """The ``"error"`` of ``--json``: how many errors, and the first."""
    errors = analysis.errors
    return f"{_count(len(errors), 'error')}; the first: {errors[0].format()}"


def _summary(analysis: Any, domain: str, problem: str | None) -> dict[str, Any]:
    """What the files declare (the ``domain`` and ``problem`` objects of ``--json``), in lower case."""
    from vslsp.symbolic.language import text_of

    index = analysis.index
    summary: dict[str, Any] = {}
    if analysis.domain_name is not None:
        summary["domain"] = {
            "name": analysis.domain_name.lower(),
            "types": [d.key for d in index.of_kind("type")],
            "constants": [d.key for d in index.of_kind("constant")],
            "predicates": [d.key for d in index.of_kind("predicate")],
            "actions": [d.key for d in index.of_kind("action")],
        }
    if problem is not None and analysis.problem_name is not None:
        sections = analysis.sections(problem)
        init = sections.get(":init")
        goal = sections.get(":goal")
        constraints = sections.get(":constraints")
        listed = constraints.items[1:] if constraints is not None else []
        if len(listed) == 1 and not isinstance(listed[0], str) and getattr(listed[0], "key", "") == "and":
            listed = listed[0].items[1:]  # type: ignore[union-attr]
        summary["problem"] = {
            "name": analysis.problem_name.lower(),
            "objects": [d.key for d in index.of_kind("object")],
            "init": sorted(text_of(atom, lower=True) for atom in (init.items[1:] if init is not None else [])),
            "goal": text_of(goal.items[1], lower=True) if goal is not None and len(goal.items) > 1 else "",
            "constraints": [text_of(c, lower=True) for c in listed],
        }
    return summary


def _print_summary(summary: dict[str, Any], domain: str, problem: str | None) -> None:
    if "domain" in summary:
        d = summary["domain"]
        click.echo(
            f"{domain}: domain {d['name']}: {_count(len(d['types']), 'type')}, predicates "
            f"{', '.join(d['predicates'])}; actions {', '.join(d['actions'])}"
        )
    if "problem" in summary:
        p = summary["problem"]
        click.echo(
            f"{problem}: problem {p['name']}: {_count(len(p['objects']), 'object')}, "
            f"{_count(len(p['init']), 'true atom')} initially, goal {p['goal']}, "
            f"{_count(len(p['constraints']), 'constraint')}"
        )
        for constraint in p["constraints"]:
            click.echo(f"  {constraint}")
    click.echo("ok")


def _count(count: int, noun: str) -> str:
    return f"{count} {noun}{'' if count == 1 else 's'}"


class ShellCommand(click.Command):
    """``vslsp shell``: its help lists the shell's commands, each with an example (read from the
    shell's command table only when the help is shown)."""

    def format_epilog(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        from vslsp.shell.commands import overview

        formatter.write_paragraph()
        formatter.write_text("Commands inside the shell (help COMMAND there tells one in full):")
        formatter.write("\n".join(line.rstrip() for line in overview().splitlines()) + "\n")


@pddl.command(cls=ShellCommand)
@click.argument("domain", type=click.Path(dir_okay=False), required=False)
@click.argument("problem", type=click.Path(dir_okay=False), required=False)
@click.option(
    "--keep-going",
    is_flag=True,
    help="Commands read from a pipe or file: exit 0 even when some were refused (default: exit 1).",
)
@max_size_option
def shell(domain: str | None, problem: str | None, keep_going: bool, max_bytes: int) -> None:
    """Author a domain and a problem interactively, starting from DOMAIN (and PROBLEM) if given:
    every command is checked as it is typed; tab completion of commands and of the names that
    fit where the cursor is; undo; history in ~/.vslsp_history. Reads commands from standard
    input when it is not a terminal (no history then); such a session exits 1 when a command
    was refused (an error, or its usage shown), unless --keep-going."""
    from vslsp.shell.save import load
    from vslsp.shell.session import Shell

    with pddl_edge(False, False):
        loaded = load(domain, problem, max_bytes) if domain else None
    session = Shell(loaded.domain if loaded else None, loaded.problem if loaded else None, loaded)
    session.max_bytes = max_bytes
    session.cmdloop()
    if session.unsaved:  # a script's output was lost: its exit code says so (the error was shown in the session)
        first = session.unsaved[0]
        more = f" (and {len(session.unsaved) - 1} more)" if len(session.unsaved) > 1 else ""
        raise type(first)(f"a save failed{more}: {first}")
    if session.errors and not keep_going and not session._interactive():
        noun = "command was" if session.errors == 1 else "commands were"
        click.echo(f"{session.errors} {noun} refused (errors above); --keep-going exits 0 regardless", err=True)
        sys.exit(1)
