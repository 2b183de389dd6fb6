"""The ``vslsp`` command line (the contract: ``docs/cli.md``).

Subcommands live in their own modules and are imported only when used, so that
``vslsp --help`` stays fast (torch and pybullet are heavy to import). To add a command,
add one entry to ``COMMANDS``: name -> "module:attribute" of a ``click.Command``.
"""

from __future__ import annotations

import importlib
import json
import os
import sys

import click

from vslsp import __version__, interrupts
from vslsp.errors import Interrupted, VslspError
from vslsp.outputs import NO_SPACE

COMMANDS: dict[str, str] = {
    "scene": "vslsp.cli.scene:scene",
    "teach": "vslsp.cli.teach:teach",
    "ground": "vslsp.cli.ground:ground",
    "pddl": "vslsp.cli.pddl:pddl",
    "shell": "vslsp.cli.pddl:shell",  # the same as `vslsp pddl shell`
    "plan": "vslsp.cli.plan:plan",
    "learn-domain": "vslsp.cli.learn_domain:learn_domain",
    "vsl": "vslsp.cli.vsl:vsl",
    "vsl3d": "vslsp.cli.vsl3d:vsl3d",
    "validate": "vslsp.cli.validate:validate",
    "lsp": "vslsp.cli.lsp:lsp",
    "experiment": "vslsp.cli.experiment:experiment",
    "demo": "vslsp.cli.demo:demo",
    "studio": "vslsp.cli.studio:studio",
}


class LazyGroup(click.Group):
    """A click group whose subcommands are imported on first use."""

    def __init__(self, *args, lazy: dict[str, str], **kwargs):
        super().__init__(*args, **kwargs)
        self._lazy = lazy

    def list_commands(self, ctx: click.Context) -> list[str]:
        return sorted(set(super().list_commands(ctx)) | set(self._lazy))

    def get_command(self, ctx: click.Context, name: str) -> click.Command | None:
        if name in self._lazy:
            module_name, attribute = self._lazy[name].split(":")
            return getattr(importlib.import_module(module_name), attribute)
        return super().get_command(ctx, name)


@click.group(cls=LazyGroup, lazy=COMMANDS, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="vslsp")
def app() -> None:
    """vslsp: Visuospatial Skill Learning for robots (VSL, VSL-3D, VSL-SP)."""


def main(argv: list[str] | None = None) -> None:
    """Entry point: runs the CLI, turning user errors into a message and an exit code.

    Under ``--json`` a failure also prints its JSON on stdout, ``{"error": ..., "exit_code": ...}``,
    so that a script reading stdout always gets one object. SIGTERM, SIGHUP and SIGQUIT raise
    :class:`~vslsp.errors.Interrupted` (as Ctrl-C raises KeyboardInterrupt), once: a second signal
    never cuts the cleanup short (:func:`vslsp.interrupts.handled`), so that every command ends
    its child processes, removes its temporary folders and keeps its finished work on the way
    out; the exit code is then 128 + the first signal's number (143, 129, 131; 130 for Ctrl-C).
    """
    args = list(sys.argv[1:] if argv is None else argv)
    wants_json = "--json" in args
    _bytes_safe_output()
    with interrupts.handled(final=True):
        try:
            _run(args, wants_json)
        except (Interrupted, KeyboardInterrupt) as stop:  # the first signal came while the command was ending
            name = getattr(stop, "signal_name", "SIGINT")
            click.echo(f"error: interrupted ({name})", err=True)
            sys.exit(interrupts.exit_code(name))
    sys.exit(0)


def _run(args: list[str], wants_json: bool) -> None:
    """The command, its errors turned into a message and an exit code (see :func:`main`)."""
    try:
        app.main(args=args, prog_name="vslsp", standalone_mode=False)
        sys.stdout.flush()  # here, so that a full disk behind stdout is a message, not a traceback at exit
    except VslspError as error:
        _fail(str(error), error.exit_code, wants_json and not getattr(error, "json_printed", False))
    except Interrupted as stop:
        _fail(f"interrupted ({stop.signal_name})", stop.exit_code, wants_json)
    except (click.exceptions.Abort, KeyboardInterrupt):
        _fail("aborted", 130, wants_json)
    except click.exceptions.Exit as done:
        _flush_or_fail()
        sys.exit(done.exit_code)
    except click.ClickException as error:
        if wants_json:
            click.echo(json.dumps({"error": error.format_message(), "exit_code": 2}))
        error.show()
        sys.exit(2)
    except OSError as error:
        if error.errno not in NO_SPACE:
            raise
        _no_space(error)


def _flush_or_fail() -> None:
    try:
        sys.stdout.flush()
    except OSError as error:
        if error.errno not in NO_SPACE:
            raise
        _no_space(error)


def _no_space(error: OSError) -> None:
    """A write failed for lack of space: one line, exit 1 (stdout is then silenced: nothing more fits)."""
    where = error.filename or "the standard output"
    try:
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
    except (OSError, ValueError):
        pass
    click.echo(f"error: cannot write {where}: {error.strerror}; free some space and run again", err=True)
    sys.exit(1)


def _bytes_safe_output() -> None:
    """Let stdout carry file names that are not UTF-8 (written back as the bytes they were typed
    with, as ``ls`` does) instead of ending the command with a UnicodeEncodeError; stderr escapes them."""
    for stream, errors in ((sys.stdout, "surrogateescape"), (sys.stderr, "backslashreplace")):
        reconfigure = getattr(stream, "reconfigure", None)
        if reconfigure is not None:
            try:
                reconfigure(errors=errors)
            except (ValueError, OSError):  # a stream already written in another way: leave it
                pass


def _fail(message: str, code: int, wants_json: bool) -> None:
    try:
        if wants_json:
            click.echo(json.dumps({"error": message, "exit_code": code}))
            sys.stdout.flush()
    except OSError as error:
        if error.errno not in NO_SPACE:
            raise
        _no_space(error)
    click.echo(f"error: {message}" if code != 130 else message, err=True)
    sys.exit(code)
