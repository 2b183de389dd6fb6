"""The author page (``/author?domain=REL&problem=REL``): domain and problem editors with the language
engine's diagnostics live as you type (marks, the message at the line's end, quick fixes), hover
titles, completion (Ctrl-Space), Save, Plan (steps and the state timeline with each constraint's
marks), Validate a plan (each violation on its step and its constraint's line), an unsolvable
problem's conflict on its lines. Paper: "Implementation" (PDDL 3.0 domains and constraints)."""

from __future__ import annotations

import asyncio
import html
import json
from pathlib import Path
from typing import Any

from nicegui import background_tasks, ui

from vslsp.errors import VslspError
from vslsp.studio import editing, engine, files
from vslsp.studio.author_navigation import Navigation
from vslsp.studio.layout import frame

STYLE = """
.vslsp-error { text-decoration: underline wavy #c62828; }
.vslsp-warning { text-decoration: underline wavy #ef6c00; }
.vslsp-line-error { background: #ffebee; } .vslsp-line-warning { background: #fff3e0; }
.vslsp-say-error { color: #c62828; font-style: italic; } .vslsp-say-warning { color: #ef6c00; font-style: italic; }
.vslsp-line-violation { background: #fce4ec; border-left: 3px solid #ad1457; }
.vslsp-line-conflict { background: #ede7f6; border-left: 3px solid #4527a0; }
.vslsp-ref { text-decoration: underline dotted #90a4ae; }
table.timeline { border-collapse: collapse; font-family: monospace; font-size: 12px; }
table.timeline td, table.timeline th { border: 1px solid #ccc; padding: 2px 6px; vertical-align: top; }
.vslsp-hover { font-family: monospace; font-size: 13px; padding: 4px 8px; background: #263238; color: #eceff1;
  border-radius: 4px; white-space: pre; }
.cm-tooltip:has(.vslsp-hover) { border: none; background: transparent; }
td.kept { background: #e8f5e9; } td.broken { background: #ffcdd2; } td.open { background: #fffde7; }
"""


#: Ctrl-Space in an editor: CodeMirror's own completion list at the cursor, its items from
#: ``POST /api/complete`` (the language engine's names that fit there, :func:`vslsp.studio.pddl.complete`).
#: A completion source in the editor's language data, which CodeMirror's autocompletion (in NiceGUI's
#: editor) asks on Ctrl-Space; offsets go to the server in characters (code points), as Python counts.
COMPLETION_JS = """
(async (ids) => {
  const CM = await import("nicegui-codemirror");
  const text = (kind) => getElement(ids[kind]).editor.state.doc.toString();
  for (const [kind, id] of Object.entries(ids)) {
    let element = getElement(id);
    while (!element || !element.editor) {
      await new Promise((resolve) => setTimeout(resolve, 50));
      element = getElement(id);
    }
    const view = element.editor;
    if (view.vslspCompletion) continue;
    view.vslspCompletion = true;
    const source = async (context) => {
      if (!context.explicit) return null;
      const doc = context.state.doc.toString();
      const at = [...doc.slice(0, context.pos)].length;
      const body = {domain: text("domain"), problem: text("problem"), in: kind, at};
      const token = document.querySelector('meta[name="vslsp-token"]')?.content || "";
      const answer = await fetch(window.path_prefix + "/api/complete", {
        method: "POST", headers: {"content-type": "application/json", "x-vslsp-token": token},
        body: JSON.stringify(body),
      });
      if (!answer.ok) return null;
      const found = await answer.json();
      const from = [...doc].slice(0, found.from).join("").length;
      const options = (found.entries || found.items.map((label) => ({label}))).map(
        (e) => ({label: e.label, type: e.type, detail: e.detail}));
      return {from, options, validFor: /^[?\\w-]*$/};
    };
    const data = CM.EditorState.languageData.of(() => [{autocomplete: source}]);
    // Hover: a name's declaration in a styled tooltip (the mark's data-hover, from the check).
    const hover = CM.hoverTooltip((view, pos) => {
      const at = view.domAtPos(pos).node;
      const element = at && (at.nodeType === 3 ? at.parentElement : at);
      const mark = element && element.closest ? element.closest("[data-hover]") : null;
      if (!mark) return null;
      return {pos, above: true, create: () => {
        const dom = document.createElement("div");
        dom.className = "vslsp-hover";
        dom.textContent = mark.dataset.hover;
        return {dom};
      }};
    });
    view.dispatch({effects: CM.StateEffect.appendConfig.of([data, hover])});
    view.dom.addEventListener("focusin", () => { window.vslspLast = kind; });
    window.vslspCompletion = {...window.vslspCompletion, [kind]: true};  // Ctrl-Space asks the server now
  }
})(%s);
"""


#: A warning before the page is left (closed, reloaded, navigated) while an editor holds unsaved edits.
LEAVE_JS = """
window.vslspUnsaved = false;
window.addEventListener("beforeunload", (event) => {
  if (window.vslspUnsaved) { event.preventDefault(); event.returnValue = ""; }
});
"""
#: How long the editors must rest before their text is checked (a burst of keys is checked once).
DEBOUNCE_S = 0.15
#: How often the opened files are looked at for changes on disk.
DISK_POLL_S = 2.0


fingerprint = files.version_of


class Author(Navigation):
    """One author page: two editors and what they show.

    Nothing typed is lost: an editor with edits not saved is marked (and leaving the page asks first);
    Save asks before it writes over a file the page did not open, or one changed on disk since it was
    opened; a change on disk is shown as it happens. The text is checked when the keys rest
    (:data:`DEBOUNCE_S`), off the event loop, and an answer for an older text than the editor's is dropped."""

    def __init__(self, root: Path, domain: str | None, problem: str | None) -> None:
        self.root = root
        self.paths = {"domain": domain or "", "problem": problem or ""}
        texts = {kind: files.read_small(root, rel) if rel else "" for kind, rel in self.paths.items()}
        #: per editor: the text as last opened or saved, the file's fingerprint then
        self.saved = dict(texts)
        self.on_disk = {kind: fingerprint(files.inside(root, rel)) if rel else None for kind, rel in self.paths.items()}
        self.version = 0
        ui.add_css(STYLE)
        ui.add_body_html(f"<script>{LEAVE_JS}</script>")
        with ui.row().classes("w-full items-center"):
            self.names = {
                kind: ui.input(f"{kind} (relative to the root)", value=self.paths[kind]).classes("w-72")
                for kind in ("domain", "problem")
            }
            ui.button("Open", on_click=self.open_files).props("id=open")
            ui.button("Save", on_click=self.save).props("id=save")
            ui.button("Plan", on_click=self.plan).props("id=plan")
            ui.button("Validate", on_click=self.validate).props("id=validate")
            ui.button("Definition", on_click=lambda: self.navigate("definition")).props("flat id=definition")
            ui.button("References", on_click=lambda: self.navigate("references")).props("flat id=references")
            ui.button("Rename", on_click=self.ask_rename).props("flat id=rename")
            ui.label("Ctrl-Space: complete the name at the cursor (F2: the names as buttons)").classes("text-grey-7")
        self.notice = ui.label().classes("text-warning disk-notice")
        self.unsaved_marks: dict[str, Any] = {}
        with ui.row().classes("w-full no-wrap"):
            self.editors: dict[str, Any] = {}
            for kind in ("domain", "problem"):
                with ui.column().classes("w-1/2"):
                    with ui.row().classes("items-center"):
                        ui.label(kind.capitalize()).classes("text-bold")
                        self.unsaved_marks[kind] = ui.label("● unsaved").classes(f"text-warning unsaved-{kind}")
                        self.unsaved_marks[kind].set_visibility(False)
                    editor = ui.codemirror(
                        texts[kind],
                        language="Common Lisp",
                        line_wrapping=True,
                        on_change=lambda _event: self.changed(),
                        keymap={
                            "F2": lambda _event, k=kind: self.complete(k),
                            "F12": lambda _event, k=kind: self.navigate("definition", k),
                            "Shift-F12": lambda _event, k=kind: self.navigate("references", k),
                        },
                    ).classes(f"w-full h-96 border editor-{kind}")
                    self.editors[kind] = editor
        self.completions = ui.row().classes("completions")
        self.found = ui.column().classes("w-full navigation")
        with ui.row().classes("w-full no-wrap"):
            self.diagnostics = ui.column().classes("w-2/3 diagnostics")
            with ui.column().classes("w-1/3"):
                ui.label("Outline").classes("text-bold")
                self.outline = ui.column().classes("outline")
        with ui.row().classes("w-full no-wrap"):
            with ui.column().classes("w-1/3"):
                ui.label("Plan to validate (one (action arg ...) per line)").classes("text-bold")
                self.plan_editor = ui.codemirror("", language="Common Lisp").classes("w-full h-48 border editor-plan")
            self.results = ui.column().classes("w-2/3 results")
        self.checked: dict = {}
        self.shown: dict[str, list[dict]] = {}
        self.drawn = True
        self.client = ui.context.client
        background_tasks.create(self.check_later(self.version, 0.0), name="vslsp-check")  # off the loop
        ids = {kind: editor.id for kind, editor in self.editors.items()}
        client = ui.context.client
        client.on_connect(lambda: client.run_javascript(COMPLETION_JS % json.dumps(ids)))
        ui.timer(DISK_POLL_S, self.look_at_disk)

    def file(self, kind: str) -> str:
        return self.names[kind].value or f"<{kind}>"

    def changed(self) -> None:
        """An edit: the unsaved marks, stale marks and buttons cleared, a check once the keys rest."""
        self.version += 1
        self.show_unsaved()
        self.completions.clear()  # F2's names were for the text before the edit
        for kind in ("problem", "plan"):
            self.mark(kind, [])  # violation and conflict marks were for the text before the edit
        background_tasks.create(self.check_later(self.version), name="vslsp-check")

    def show_unsaved(self) -> None:
        dirty = {kind: editor.value != self.saved[kind] for kind, editor in self.editors.items()}
        for kind, mark in self.unsaved_marks.items():
            mark.set_visibility(dirty[kind])
        ui.run_javascript(f"window.vslspUnsaved = {'true' if any(dirty.values()) else 'false'};")

    async def check_later(self, version: int, rest: float = DEBOUNCE_S) -> None:
        await asyncio.sleep(rest)
        if version != self.version:
            return  # more keys came: the newest edit checks
        await self.client.connected()
        domain, problem = self.editors["domain"].value, self.editors["problem"].value
        names = (self.file("domain"), self.file("problem"))
        try:
            answer = await engine.call("check", domain, problem or None, *names)
        except VslspError:
            return
        if version == self.version:  # an answer for an older text is dropped
            self.show_check(answer)

    def look_at_disk(self) -> None:
        """Say when an opened file changed on disk (another editor, git) since the page opened or saved it."""
        changed = []
        for kind, rel in self.paths.items():
            if rel and self.on_disk[kind] is not None:
                try:
                    now = fingerprint(files.inside(self.root, rel, must_exist=False))
                except VslspError:
                    continue
                if now != self.on_disk[kind]:
                    changed.append(rel)
        self.notice.set_text(
            f"changed on disk since opened: {', '.join(changed)} (Open to load it; Save asks before writing over it)"
            if changed
            else ""
        )

    def show_check(self, checked: dict) -> None:
        """Marks, messages, quick fixes and the outline of a check redrawn."""
        self.checked = checked
        self.show_outline()
        for kind, editor in self.editors.items():
            found, tips = editing.decorations(editor.value, self.file(kind), self.checked)
            self.draw(kind, found, tips)
        self.diagnostics.clear()
        with self.diagnostics:
            for diagnostic in self.checked["diagnostics"]:
                with ui.row().classes(f"items-center diagnostic diagnostic-{diagnostic['severity']}"):
                    where = f"{diagnostic['file']}:{diagnostic['line']}:{diagnostic['column']}"
                    ui.label(f"{where}: {diagnostic['severity']}: {diagnostic['message']}")
                    for fix in diagnostic["fixes"]:
                        ui.button(fix["title"], on_click=lambda _e, f=fix, d=diagnostic: self.apply(d, f)).props(
                            "flat dense no-caps"
                        ).classes("quick-fix")
            if not self.checked["diagnostics"]:
                ui.label("no errors, no warnings").classes("text-positive no-diagnostics")

    def apply(self, diagnostic: dict, fix: dict) -> None:
        kind = next((k for k in self.editors if self.file(k) == diagnostic["file"]), "domain")
        text = self.editors[kind].value
        starts = editing.line_starts(text)
        begin = editing.offset(starts, text, fix["line"], fix["column"])
        end = editing.offset(starts, text, fix["end_line"], fix["end_column"])
        self.editors[kind].value = text[:begin] + fix["text"] + text[end:]
        self.changed()

    async def complete(self, kind: str) -> None:
        editor = self.editors[kind]
        at = await ui.run_javascript(f"getElement({editor.id}).editor.state.selection.main.head")
        offered = editing.complete(editor.value, int(at), self.checked, kind == "problem")
        self.completions.clear()
        with self.completions:
            for item in offered["items"]:
                ui.button(item, on_click=lambda _e, i=item: self.insert(kind, offered["from"], int(at), i)).props(
                    "dense outline no-caps"
                ).classes("completion")

    def insert(self, kind: str, begin: int, end: int, text: str) -> None:
        value = self.editors[kind].value
        self.editors[kind].value = value[:begin] + text + value[end:]
        self.changed()

    def open_files(self) -> None:
        query = "&".join(f"{k}={self.names[k].value}" for k in ("domain", "problem") if self.names[k].value)
        ui.navigate.to(f"/author?{query}")

    def risks(self) -> list[str]:
        """What Save would write over without the user having seen it: a file the page did not open, or
        one that changed on disk since it was opened or saved."""
        found = []
        for kind in self.editors:
            rel = self.names[kind].value
            if not rel:
                continue
            try:
                now = fingerprint(files.inside(self.root, rel, must_exist=False))
            except VslspError:
                continue  # refused again, with its message, when written
            if now is None:
                continue
            if rel != self.paths[kind]:
                found.append(f"{rel} exists and is not the file this page opened")
            elif now != self.on_disk[kind]:
                found.append(f"{rel} changed on disk since this page opened it")
        return found

    async def save(self) -> None:
        risks = self.risks()
        if risks:
            with ui.dialog() as dialog, ui.card():
                for risk in risks:
                    ui.label(risk).classes("save-risk")
                ui.label("Write over it?")
                with ui.row():
                    ui.button("Overwrite", on_click=lambda: dialog.submit(True)).props("id=overwrite")
                    ui.button("Cancel", on_click=lambda: dialog.submit(False)).props("flat id=keep")
            if not await dialog:
                ui.notify("not saved", type="warning")
                return
        try:
            for kind, editor in self.editors.items():
                rel = self.names[kind].value
                if rel:
                    text = editor.value
                    written = files.write_text(self.root, rel, text)
                    self.paths[kind], self.saved[kind], self.on_disk[kind] = rel, text, fingerprint(written)
        except VslspError as error:
            ui.notify(str(error), type="negative")
            return
        self.show_unsaved()
        self.look_at_disk()
        ui.notify("saved", type="positive")

    def _texts(self) -> tuple[str, str, str, str]:
        return (self.editors["domain"].value, self.editors["problem"].value, self.file("domain"), self.file("problem"))

    async def plan(self) -> None:
        self.results.clear()
        with self.results:
            ui.spinner()
        domain, problem, domain_file, problem_file = self._texts()
        try:
            answer = await engine.call("plan", domain, problem, domain_file, problem_file)
        except VslspError as error:
            answer = {
                "plan": None,
                "error": str(error),
                "conflict": getattr(error, "conflict", None),
                "reasons": getattr(error, "reasons", []),
            }
        self.results.clear()
        self.mark("problem", [])
        with self.results:
            if answer.get("plan") is None:
                message = str(answer["error"])
                said = message if message.startswith("no plan") else f"no plan: {message}"
                ui.label(said).classes("text-negative plan-error")
                self.show_conflict(answer.get("conflict") or [], answer.get("reasons") or [])
                return
            ui.label(f"plan: {len(answer['plan'])} steps ({answer['planner']}, {answer['time_s']:.2f} s)")
            with ui.element("ol").classes("plan-steps"):
                for step in answer["plan"]:
                    with ui.element("li").classes("plan-step"):
                        ui.label(f"({step})")
            self.plan_editor.value = "".join(f"({step})\n" for step in answer["plan"])
            self.timeline(answer["timeline"], set())

    def show_conflict(self, conflict: list[dict], reasons: tuple[str, ...] | list[str] = ()) -> None:
        if not conflict:
            return
        ui.label("these cannot all hold (a minimal conflict):").classes("text-bold")
        for item in conflict:
            ui.label(f"line {item.get('line')}: {item.get('kind')} {item.get('text')}").classes("conflict-item")
        for reason in reasons:
            ui.label(f"because: {reason}").classes("conflict-reason")
        self.mark("problem", [(i["line"], "conflict", str(i.get("text"))) for i in conflict if i.get("line")])

    async def validate(self) -> None:
        domain, problem, domain_file, problem_file = self._texts()
        plan_text = self.plan_editor.value
        self.results.clear()
        try:
            answer = await engine.call("validate", domain, problem, plan_text, domain_file, problem_file)
        except VslspError as error:
            with self.results:
                ui.label(str(error)).classes("text-negative validate-error")
            return
        with self.results:
            verdict = "valid" if answer["valid"] else "invalid"
            lines = editing.formula_lines(problem, problem_file)
            violations = self.violations(answer, lines)
            listed = {v["message"] for v in violations}
            reason = "" if answer["reason"] in listed else f": {answer['reason']}"  # each message once
            count = f" ({len(violations)} violation{'s' * (len(violations) != 1)})" if violations else ""
            ui.label(f"{verdict}{reason}{count}").classes(f"verdict verdict-{verdict}")
            for violation in violations:
                ui.label(violation["message"]).classes("violation")
            self.mark("problem", [(v["line"], "violation", v["message"]) for v in violations if v.get("line")])
            self.mark("plan", [(v["step"], "violation", v["message"]) for v in violations if v.get("step")])
            self.timeline(answer["timeline"], {v["step"] for v in violations if v.get("step")})

    @staticmethod
    def violations(answer: dict, lines: dict) -> list[dict]:
        """Every violation with its problem line and plan step: the symbolic layer's own list where it
        gives one, else the timeline's broken constraints and the step that did not apply."""
        if "violations" in answer:
            return [
                {**v, "line": v.get("line") if v.get("file") != "<plan>" else None, "step": v.get("step")}
                for v in answer["violations"]
            ]
        if answer["valid"]:
            return []
        timeline, found = answer["timeline"], []
        for number, constraint in enumerate(timeline["constraints"]):
            if "broken" in constraint["status"]:
                step = constraint["status"].index("broken")
                line = lines["constraints"][number]["line"] if number < len(lines["constraints"]) else None
                message = f"{constraint['text']} is broken after step {step}"
                found.append({"kind": "constraint", "line": line, "step": step, "message": message})
        if not found:
            applied = len(timeline["steps"])
            found.append({"kind": "plan", "line": lines.get("goal"), "step": applied + 1, "message": answer["reason"]})
        return found

    def draw(self, kind: str, found: list[dict], tips: dict[int, str] | None = None) -> None:
        """Decorations (and line tooltips) through the editor's own methods, not its props: a props
        update would send the server's copy of the text too, which lags the keys still in flight."""
        editor = self.plan_editor if kind == "plan" else self.editors[kind]
        self.shown[kind] = found
        if not self.drawn:  # the page is being built: its props go out with it
            editor.decorations = found
            editor.line_tooltips = tips or {}
            return
        editor.run_method("setDecorations", found)
        if tips is not None:
            editor.run_method("setLineTooltips", {str(line): text for line, text in tips.items()})

    def mark(self, kind: str, marks: list[tuple[int, str, str]]) -> None:
        kept = [
            d
            for d in self.shown.get(kind, [])
            if not str(d.get("class", "")).startswith(("vslsp-line-violation", "vslsp-line-conflict"))
        ]
        for line, what, message in marks:
            kept.append(
                {"kind": "line", "line": int(line), "class": f"vslsp-line-{what}", "attributes": {"title": message}}
            )
        self.draw(kind, kept)

    def timeline(self, timeline: dict, flagged: set[int]) -> None:
        """States s_0..s_n as rows: the step, the atoms true after it, each constraint's mark."""
        marks = {"kept": "✓ kept", "broken": "✗ broken", "open": "… open"}
        head = "".join(f"<th>{html.escape(c['text'])}</th>" for c in timeline["constraints"])
        rows = []
        for i, atoms in enumerate(timeline["states"]):
            step = "initial state" if i == 0 else f"{i}. ({timeline['steps'][i - 1]})"
            cells = "".join(
                f"<td class='{c['status'][i]}'>{marks[c['status'][i]]}</td>" for c in timeline["constraints"]
            )
            flag = " class='flagged'" if i in flagged else ""
            rows.append(f"<tr{flag}><td>{html.escape(step)}</td><td>{html.escape(' '.join(atoms))}</td>{cells}</tr>")
        table = f"<table class='timeline'><tr><th>after</th><th>atoms true</th>{head}</tr>{''.join(rows)}</table>"
        ui.html(table, sanitize=False).classes("timeline-view")


def register(root: Path) -> None:
    @ui.page("/author")
    def author_page(domain: str | None = None, problem: str | None = None) -> None:
        frame("Author")
        try:
            Author(root, domain, problem)
        except VslspError as error:
            ui.label(str(error)).classes("text-negative page-error")
