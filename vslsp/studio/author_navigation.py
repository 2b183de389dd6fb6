"""The author page's navigation (:class:`Navigation`, a part of :class:`vslsp.studio.author.Author`): go
to definition (F12), references (Shift-F12), rename and the outline of both editors, from the language
engine's index (:mod:`vslsp.studio.navigation`, in the studio's worker pool)."""

from __future__ import annotations

from typing import Any

from nicegui import ui

from vslsp.errors import VslspError
from vslsp.studio import editing, engine

#: The cursor of an editor in code points (as Python counts), and a move of its selection to a 1-based
#: line and column range (code points), scrolled into view.
CURSOR_JS = """(() => {
  const v = getElement(%d).editor;
  return [...v.state.doc.sliceString(0, v.state.selection.main.head)].length;
})()"""
GOTO_JS = """(() => {
  const v = getElement(%d).editor, doc = v.state.doc;
  const at = (line, column) => { const l = doc.line(Math.max(1, Math.min(line, doc.lines)));
    return l.from + [...l.text].slice(0, Math.max(0, column - 1)).join("").length; };
  v.dispatch({selection: {anchor: at(%d, %d), head: at(%d, %d)}, scrollIntoView: true});
  v.focus();
})()"""


class Navigation:
    """What the author page does with the names of its texts (needs ``editors``, ``checked``, ``found``,
    ``outline``, ``file``, ``_texts`` and ``changed`` of the page)."""

    editors: dict[str, Any]
    checked: dict
    found: Any
    outline: Any

    def file(self, kind: str) -> str:
        raise NotImplementedError

    def _texts(self) -> tuple[str, str, str, str]:
        raise NotImplementedError

    def changed(self) -> None:
        raise NotImplementedError

    def show_outline(self) -> None:
        self.outline.clear()
        with self.outline:
            for kind in self.editors:
                for item in self.checked.get("outline", {}).get(self.file(kind), []):
                    for entry, depth in [(item, 0), *((child, 1) for child in item["children"])]:
                        ui.button(
                            f"{'    ' * depth}{entry['kind']} {entry['name']}",
                            on_click=lambda _e, k=kind, e=entry: self.go(k, e["line"], e["column"]),
                        ).props("flat dense no-caps align=left").classes(f"outline-item outline-{kind}")

    def go(self, kind: str | None, line: int, column: int, end_line: int | None = None, end_column: int | None = None):
        if kind in self.editors:
            editor = self.editors[kind]
            ui.run_javascript(GOTO_JS % (editor.id, line, column, end_line or line, end_column or column))

    async def cursor(self, kind: str | None) -> tuple[str, int]:
        """The editor asked about (the one last focused when none is named) and its cursor's offset."""
        if kind is None:
            kind = await ui.run_javascript("window.vslspLast || 'domain'")
            kind = kind if kind in self.editors else "domain"
        return kind, int(await ui.run_javascript(CURSOR_JS % self.editors[kind].id))

    async def navigate(self, what: str, kind: str | None = None, new_name: str | None = None) -> dict | None:
        """Definition (the cursor goes there), references (listed, each a link), rename (applied to both
        editors) of the name at the cursor; the language server's features on the page's two texts."""
        kind, at = await self.cursor(kind)
        domain, problem, domain_file, problem_file = self._texts()
        try:
            answer = await engine.call(
                "navigate", domain, problem or None, kind, at, what, new_name, domain_file, problem_file
            )
        except VslspError as error:
            ui.notify(str(error), type="negative")
            return None
        self.found.clear()
        if answer.get("name") is None:
            with self.found:
                ui.label("no declared name at the cursor").classes("text-grey-7 navigation-none")
            return answer
        if what == "definition":
            place = answer["locations"][0]
            with self.found:
                ui.label(f"{answer['kind']} {answer['signature']}: {place['file']}:{place['line']}:{place['column']}")
            self.go(place["in"], place["line"], place["column"], place["end_line"], place["end_column"])
        elif what == "references":
            with self.found:
                ui.label(f"{len(answer['locations'])} places name {answer['kind']} {answer['name']}").classes(
                    "references-title"
                )
                for place in answer["locations"]:
                    ui.button(
                        f"{place['file']}:{place['line']}:{place['column']}",
                        on_click=lambda _e, p=place: self.go(
                            p["in"], p["line"], p["column"], p["end_line"], p["end_column"]
                        ),
                    ).props("flat dense no-caps").classes("reference")
        return answer

    async def ask_rename(self) -> None:
        kind, at = await self.cursor(None)
        with ui.dialog() as dialog, ui.card():
            ui.label("Rename the name at the cursor everywhere it is named, to:")
            name = ui.input("new name").props("autofocus").classes("rename-to")
            with ui.row():
                ui.button("Rename", on_click=lambda: dialog.submit(name.value)).props("id=rename-ok")
                ui.button("Cancel", on_click=lambda: dialog.submit(None)).props("flat")
        new_name = await dialog
        if not new_name:
            return
        domain, problem, domain_file, problem_file = self._texts()
        try:
            answer = await engine.call(
                "navigate", domain, problem or None, kind, at, "rename", new_name, domain_file, problem_file
            )
        except VslspError as error:
            ui.notify(str(error), type="negative")
            return
        for editor_kind, editor in self.editors.items():
            edits = [e for e in answer["edits"] if e["in"] == editor_kind]
            text = editor.value
            starts = editing.line_starts(text)
            for edit in sorted(edits, key=lambda e: (e["line"], e["column"]), reverse=True):
                begin = editing.offset(starts, text, edit["line"], edit["column"])
                end = editing.offset(starts, text, edit["end_line"], edit["end_column"])
                text = text[:begin] + edit["text"] + text[end:]
            if edits:
                editor.value = text
        ui.notify(f"renamed {answer['name']} to {new_name} in {len(answer['edits'])} places")
        self.changed()
