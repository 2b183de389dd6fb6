"""The studio's page frame: a header with the four pages."""

from __future__ import annotations

import html
from collections.abc import Callable
from typing import Any

from nicegui import run, ui

from vslsp.errors import InputError

PAGES = (("Author", "/author"), ("Ground", "/ground"), ("Experiments", "/experiments"), ("Reports", "/reports"))


#: The session's secret, written into every page for its own requests to the API (``X-Vslsp-Token``):
#: another origin cannot read the page, so it cannot learn it (:mod:`vslsp.studio.guard`).
PAGE_TOKEN: dict[str, str] = {}


def frame(title: str) -> None:
    """The header of every page (``title`` is the page's own)."""
    ui.page_title(f"vslsp studio: {title}")
    if "token" in PAGE_TOKEN:
        ui.add_head_html(f'<meta name="vslsp-token" content="{html.escape(PAGE_TOKEN["token"])}">')
    with ui.header().classes("items-center bg-blue-grey-9"):
        ui.label("vslsp studio").classes("text-h6")
        for name, link in PAGES:
            ui.link(name, link).classes("text-white" + (" text-bold" if name == title else ""))


async def in_thread(work: Callable[..., dict], *args: Any) -> dict:
    """``work(*args)`` in a worker thread (planning, grounding), so the page stays live."""
    answer = await run.io_bound(work, *args)
    if answer is None:
        raise InputError("the studio is stopping; start it again")
    return answer
