"""The studio's page frame: a header with the four pages."""

from __future__ import annotations

from nicegui import ui

PAGES = (("Author", "/author"), ("Ground", "/ground"), ("Experiments", "/experiments"), ("Reports", "/reports"))


def frame(title: str) -> None:
    """The header of every page (``title`` is the page's own)."""
    ui.page_title(f"vslsp studio: {title}")
    with ui.header().classes("items-center bg-blue-grey-9"):
        ui.label("vslsp studio").classes("text-h6")
        for name, link in PAGES:
            ui.link(name, link).classes("text-white" + (" text-bold" if name == title else ""))
