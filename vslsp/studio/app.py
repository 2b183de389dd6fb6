"""Serving the studio: the NiceGUI app with the API (:mod:`vslsp.studio.api`) and the pages.

Start-up (docs/studio.md, "Speed"): most of it is importing the web stack (NiceGUI, FastAPI,
socket.io); the pages import what they need (the planner, grounding, numpy, the experiments) when
first used.
"""

from __future__ import annotations

import sys
from pathlib import Path

#: Modules only the client side of socket.io imports (engineio's Client and AsyncClient): the studio
#: serves and never connects out, so they are kept out of its start-up (a quarter of a second and
#: more), and importable again right after (engineio's client is then left without them).
CLIENT_ONLY = ("aiohttp", "requests", "websocket")


def import_web_stack() -> None:
    """Import NiceGUI (ImportError when the studio extra is not installed), without :data:`CLIENT_ONLY`."""
    kept_out = [name for name in CLIENT_ONLY if name not in sys.modules]
    for name in kept_out:
        sys.modules[name] = None  # type: ignore[assignment]  # ``import name`` fails: engineio's client goes without
    try:
        import nicegui  # noqa: F401
    finally:
        for name in kept_out:
            if sys.modules.get(name, 0) is None:
                del sys.modules[name]


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
