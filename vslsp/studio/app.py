"""Serving the studio: the NiceGUI app with the API (:mod:`vslsp.studio.api`) and the pages.

Start-up (docs/studio.md, "Speed"): most of it is importing the web stack (NiceGUI, FastAPI,
socket.io); the pages import what they need (the planner, grounding, numpy, the experiments) when
first used.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from vslsp.studio.guard import Access
    from vslsp.studio.settings import Settings

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


def build(root: Path, access: Access, settings: Settings) -> None:
    """Register the guard, the API, the files, the pages and the job queue on NiceGUI's app."""
    from nicegui import app

    from vslsp.studio import api, author, engine, layout, pages, runs

    layout.PAGE_TOKEN["token"] = access.token
    api.install(app, root, access, settings)
    author.register(root)
    pages.register(root, settings)
    app.on_startup(lambda: runs.queue(root).pump())  # jobs an earlier studio left queued
    app.on_startup(warm_up)
    app.on_startup(engine.warm_up)
    app.on_shutdown(engine.shut_down)


def warm_up() -> None:
    """Import the experiment registry in a thread at start-up, so that the first run's check does not."""
    import threading

    def load() -> None:
        from vslsp.tasks import list_tasks

        list_tasks()

    threading.Thread(target=load, name="vslsp-studio-warm-up", daemon=True).start()


def serve(root: Path, host: str, port: int, access: Access, settings: Settings, show: bool | str) -> None:
    """Run the studio until interrupted (uvicorn in this process); ``show``: the page to open in a browser."""
    from nicegui import ui

    build(root, access, settings)
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
