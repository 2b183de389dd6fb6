"""``vslsp studio``: the local web app (docs/studio.md). The web stack is imported only here, when
the command runs, so that the other commands stay fast and the studio stays an optional extra."""

from __future__ import annotations

import ipaddress
import secrets
import socket
from pathlib import Path

import click

from vslsp.errors import InputError

LOOPBACK = ("127.0.0.1", "localhost", "::1")


def _loopback(host: str) -> bool:
    if host in LOOPBACK:
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


@click.command()
@click.option("--root", type=click.Path(file_okay=False), default=".", show_default=True, help="The folder served.")
@click.option("--host", default="127.0.0.1", show_default=True, help="Address to bind (beyond loopback: a token).")
@click.option("--port", type=click.IntRange(1, 65535), default=8765, show_default=True)
@click.option("--no-browser", is_flag=True, help="Do not open a browser.")
@click.option(
    "--token",
    default=None,
    help="Required on every request when --host is not a loopback address (generated and printed if not given).",
)
def studio(root: str, host: str, port: int, no_browser: bool, token: str | None) -> None:
    """Serve the studio over the files under --root: author PDDL, ground images, run experiments,
    read reports. Everything stays under the root; runs go on when the page is closed."""
    folder = Path(root)
    if not folder.is_dir():
        raise InputError(f"--root {root}: no such folder")
    if token is not None and len(token) < 16:
        raise InputError("--token: give at least 16 characters (or leave it out to get one generated)")
    if not _loopback(host) and token is None:
        token = secrets.token_urlsafe(24)
    from vslsp.studio.app import import_web_stack

    try:
        import_web_stack()
    except ImportError:
        raise InputError("the studio needs its extra: pip install 'vslsp[studio]'") from None
    _check_port(host, port)
    from vslsp.studio.app import serve

    address = f"http://{'[' + host + ']' if ':' in host else host}:{port}/author"
    if token is not None:
        address += f"?token={token}"
    click.echo(f"vslsp studio: {address} (root {folder.resolve()}); Ctrl-C stops it", err=True)
    serve(folder.resolve(), host, port, token, False if no_browser else address.split(f":{port}", 1)[1])


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
