"""``vslsp studio``: the local web app (docs/studio.md). The web stack is imported only here, when
the command runs, so that the other commands stay fast and the studio stays an optional extra."""

from __future__ import annotations

import secrets
import socket
from pathlib import Path

import click

from vslsp.cli.params import int_range
from vslsp.errors import InputError


@click.command()
@click.option("--root", type=click.Path(file_okay=False), default=".", show_default=True, help="The folder served.")
@click.option("--host", default="127.0.0.1", show_default=True, help="Address to bind (beyond loopback: a token).")
@click.option("--port", type=int_range(1, 65535), default=8765, show_default=True)
@click.option("--no-browser", is_flag=True, help="Do not open a browser.")
@click.option(
    "--token",
    default=None,
    help="The secret every request needs (default: a new one each start, printed in the address it opens).",
)
@click.option(
    "--allow-host",
    "allow_hosts",
    multiple=True,
    help="A further host name the browser may use to reach the studio (a proxy's or the machine's DNS name).",
)
@click.option(
    "--max-runs",
    type=int_range(1, 64),
    default=2,
    show_default=True,
    help="Runs and picture jobs that run at once; the others wait in a queue.",
)
@click.option("--edit-code", is_flag=True, help="Let the predicates editor save .py files under the root.")
@click.option(
    "--tasks",
    "task_files",
    type=click.Path(dir_okay=False),
    multiple=True,
    help="A Python file of your own tasks (as vslsp experiment --tasks): offered in the run form and run by "
    "its jobs; chosen here, never by a request. Repeatable.",
)
def studio(
    root: str,
    host: str,
    port: int,
    no_browser: bool,
    token: str | None,
    allow_hosts: tuple[str, ...],
    max_runs: int,
    edit_code: bool,
    task_files: tuple[str, ...],
) -> None:
    """Serve the studio over the files under --root: author PDDL, ground images, run experiments,
    read reports. Everything stays under the root; runs go on when the page is closed. Every request
    needs the session's secret (docs/studio.md, "Threat model")."""
    folder = Path(root)
    if not folder.is_dir():
        raise InputError(f"--root {root}: no such folder")
    if token is not None and (len(token) < 16 or not token.isascii() or not token.isprintable() or " " in token):
        raise InputError("--token: give at least 16 printable ASCII characters without spaces (or leave it out)")
    token = token or secrets.token_urlsafe(24)
    for name in allow_hosts:
        if not name or any(c in name for c in "/:@ ") or not name.isascii():
            raise InputError(f"--allow-host {name!r}: give a host name such as studio.example.org (no port)")
    from vslsp.studio.app import import_web_stack

    try:
        import_web_stack()
    except ImportError:
        raise InputError("the studio needs its extra: pip install 'vslsp[studio]'") from None
    _check_port(host, port)
    from vslsp.tasks import load_task_files

    load_task_files(task_files)  # the registry of the studio and (by VSLSP_TASK_FILES) of its jobs
    from vslsp.studio.app import serve
    from vslsp.studio.guard import Access
    from vslsp.studio.settings import Settings

    shown = "127.0.0.1" if host in ("0.0.0.0", "::") else host
    address = f"http://{'[' + shown + ']' if ':' in shown else shown}:{port}/author?token={token}"
    access = Access(token=token, bound=host, port=port, hosts=frozenset(n.lower() for n in allow_hosts))
    settings = Settings(max_jobs=max_runs, edit_code=edit_code)
    click.echo(f"vslsp studio: {address} (root {folder.resolve()}); Ctrl-C stops it", err=True)
    serve(folder.resolve(), host, port, access, settings, False if no_browser else address.split(f":{port}", 1)[1])


def _check_port(host: str, port: int) -> None:
    """InputError before any work when the address cannot be bound (in use, or not this machine's)."""
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    with socket.socket(family, socket.SOCK_STREAM) as probe:
        probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            probe.bind((host, port))
        except OSError as error:
            raise InputError(
                f"cannot serve on {host}:{port} ({error.strerror}); choose another --port or --host"
            ) from None
