"""``vslsp pddl check DOMAIN [PROBLEM]``: read PDDL 3.0 files and report what is in them or wrong.

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


@contextmanager
def pddl_edge(as_json: bool, debug: bool, failure: dict[str, Any] | None = None) -> Iterator[list[str]]:
    """Run a PDDL command: collects the PddlWarnings (the list yielded, printed on stderr at the end);
    on an error prints ``failure`` + ``{"error": ...}`` as JSON when ``as_json``, the traceback when ``debug``."""
    from vslsp.symbolic import InternalError, PddlWarning

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
                    {**(failure or {}), "error": str(error), "exit_code": error.exit_code, "warnings": collected}
                )
            )
            error.json_printed = True  # type: ignore[attr-defined]
        raise error from None


def debug_option(function: Any) -> Any:
    return click.option("--debug", is_flag=True, help="Show the traceback of an internal error (exit 3).")(function)


@click.group()
def pddl() -> None:
    """Work with PDDL 3.0 domain and problem files."""


@pddl.command()
@click.argument("domain", type=click.Path(dir_okay=False))
@click.argument("problem", type=click.Path(dir_okay=False), required=False)
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object on stdout.")
@debug_option
def check(domain: str, problem: str | None, as_json: bool, debug: bool) -> None:
    """Parse DOMAIN (and PROBLEM); malformed input is reported as FILE:LINE:COL (exit 2)."""
    from vslsp.symbolic import read_pddl

    with pddl_edge(as_json, debug) as warned:
        parsed_domain, parsed_problem = read_pddl(domain, problem)
    summary: dict[str, Any] = {
        "domain": {
            "name": parsed_domain.name,
            "types": [name for name, _ in parsed_domain.types],
            "constants": [name for name, _ in parsed_domain.constants],
            "predicates": [p.name for p in parsed_domain.predicates],
            "actions": [a.name for a in parsed_domain.actions],
        },
        "warnings": warned,
    }
    if parsed_problem is not None:
        summary["problem"] = {
            "name": parsed_problem.name,
            "objects": [name for name, _ in parsed_problem.objects],
            "init": sorted(atom.to_pddl() for atom in parsed_problem.init),
            "goal": parsed_problem.goal.to_pddl(),
            "constraints": [c.to_pddl() for c in parsed_problem.constraints],
        }
    if as_json:
        click.echo(json.dumps(summary))
        return
    d = summary["domain"]
    click.echo(
        f"{domain}: domain {d['name']}: {_count(len(d['types']), 'type')}, predicates "
        f"{', '.join(d['predicates'])}; actions {', '.join(d['actions'])}"
    )
    if parsed_problem is not None:
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
        from vslsp.symbolic.shell_commands import overview

        formatter.write_paragraph()
        formatter.write_text("Commands inside the shell (help COMMAND there tells one in full):")
        formatter.write("\n".join(line.rstrip() for line in overview().splitlines()) + "\n")


@pddl.command(cls=ShellCommand)
@click.argument("domain", type=click.Path(dir_okay=False), required=False)
@click.argument("problem", type=click.Path(dir_okay=False), required=False)
def shell(domain: str | None, problem: str | None) -> None:
    """Author a domain and a problem interactively, starting from DOMAIN (and PROBLEM) if given:
    every command is checked as it is typed; tab completion of commands and of the names that
    fit where the cursor is; undo; history in ~/.vslsp_history. Reads commands from standard
    input when it is not a terminal (no history then)."""
    from vslsp.symbolic import read_pddl
    from vslsp.symbolic.shell import Shell

    with pddl_edge(False, False):
        parsed_domain, parsed_problem = read_pddl(domain, problem) if domain else (None, None)
    Shell(parsed_domain, parsed_problem).cmdloop()
