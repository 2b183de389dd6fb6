"""Serving the studio: the NiceGUI app with the API (:mod:`vslsp.studio.api`) and the pages."""

from __future__ import annotations

from pathlib import Path


def build(root: Path, token: str | None) -> None:
    """Register the API, the files and the pages on NiceGUI's app."""
    from nicegui import app

    from vslsp.studio import api, author, pages

    api.install(app, root, token)
    author.register(root)
    pages.register(root)


def serve(root: Path, host: str, port: int, token: str | None, show: bool | str) -> None:
    """Run the studio until interrupted (uvicorn in this process); ``show``: the page to open in a browser."""
    from nicegui import ui

    build(root, token)
    ui.run(
        host=host,
        port=port,
        title="vslsp studio",
        show=show,
        reload=False,
        show_welcome_message=False,
        storage_secret=None,
        favicon="🤖",
    )
