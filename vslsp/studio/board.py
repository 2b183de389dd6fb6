"""The experiments page's runs, live: each run's state, trials done and successes so far, and the
newest picture of its current trial (what its cameras last saw, :mod:`vslsp.sim.live`), refreshed every
second in place (a picture is fetched again only when it changed)."""

from __future__ import annotations

from pathlib import Path
from typing import Any
from urllib.parse import quote

from nicegui import ui

from vslsp.studio import runs

#: The newest runs the board shows.
SHOWN = 20


class RunBoard:
    """The runs under the root, newest first (each a card, kept and updated as its status changes)."""

    def __init__(self, root: Path) -> None:
        self.root = root
        self.column = ui.column().classes("w-full runs")
        self.cards: dict[str, dict[str, Any]] = {}
        self.refresh()
        ui.timer(1.0, self.refresh)

    def refresh(self) -> None:
        statuses = runs.listing(self.root)[:SHOWN]
        for position, status in enumerate(statuses):
            card = self.cards.get(status["id"])
            if card is None:
                card = self.cards[status["id"]] = self._card()
                card["card"].move(self.column, target_index=position)
            self._update(card, status)
        for gone in set(self.cards) - {status["id"] for status in statuses}:
            self.cards.pop(gone)["card"].delete()

    def _card(self) -> dict[str, Any]:
        with self.column, ui.card().classes("w-full run") as card:
            with ui.row().classes("items-center"):
                text = ui.label().classes("run-text")
                links = ui.row()
                cancel = ui.button("Cancel").props("flat dense no-caps").classes("cancel-run")
            error = ui.label().classes("text-negative")
            picture = ui.image().classes("w-96 live-picture")
            caption = ui.label().classes("text-caption live-caption")
        picture.set_visibility(False)
        found = {"card": card, "text": text, "links": links, "error": error, "picture": picture, "caption": caption}
        found["cancel"] = cancel
        cancel.on_click(lambda: self.cancel(found))
        return found

    async def cancel(self, card: dict[str, Any]) -> None:
        from vslsp.errors import VslspError
        from vslsp.studio.layout import in_thread

        try:
            await in_thread(runs.queue(self.root).cancel, runs.RUNS, card["id"], "run")
        except VslspError as error:
            ui.notify(str(error), type="warning")
            return
        ui.notify(f"cancelling run {card['id']}")
        self.refresh()

    def _update(self, card: dict[str, Any], status: dict) -> None:
        request = status.get("request") or {}
        state, done, total = status["state"], status["done"], status["total"]
        card["id"] = status["id"]
        card["cancel"].set_visibility(state in ("queued", "running"))
        now = f", trial {done + 1} of {total} running" if state == "running" and done < total else ""
        if state == "queued" and status.get("position"):
            now = f", number {status['position']} in the queue"
        card["text"].set_text(
            f"{status['id']}: {request.get('experiment')} — {state}, {done}/{total} trials, "
            f"{status['successes']} succeeded{now}"
        )
        card["card"].classes(replace=f"w-full run run-{state}")
        card["error"].set_text(status.get("error") or "")
        if status.get("report") and not card.get("report"):
            with card["links"]:
                ui.link("report", f"/reports/{status['report']}").classes("report-link")
            card["report"] = status["report"]
        latest = status.get("latest")
        if latest:
            try:
                version = (self.root.resolve() / latest).stat().st_mtime_ns
            except OSError:
                return
            source = "/files/" + quote(latest) + f"?v={version}"
            if card["picture"].source != source:
                card["picture"].set_source(source)
                card["caption"].set_text(f"the newest picture: {latest}")
                card["picture"].set_visibility(True)
