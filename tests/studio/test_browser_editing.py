"""The author page as an editor (issue 40): a styled hover, completion with kinds, go to definition,
references, rename, the outline, and nothing typed lost (the unsaved mark, Save asking before it
writes over a file the page did not open or one changed on disk)."""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers.studio import CHROMIUM

pytestmark = pytest.mark.skipif(not Path(CHROMIUM).exists(), reason=f"no {CHROMIUM} (apt-get install chromium)")
pytest.importorskip("playwright.sync_api", reason="pip install playwright")


def _author(page, studio: str) -> None:
    page.goto(f"{studio}/author?domain=pddl/domain.pddl&problem=pddl/pull-in-order.pddl")
    page.locator(".editor-domain .cm-content").wait_for()
    page.locator(".no-diagnostics").wait_for()
    page.wait_for_function("window.vslspCompletion && window.vslspCompletion.domain")


def _cursor_in(page, has_text: str, back: int) -> None:
    page.locator(".editor-domain .cm-line", has_text=has_text).first.click()
    page.keyboard.press("End")
    for _ in range(back):
        page.keyboard.press("ArrowLeft")


def test_hover_shows_the_declaration_in_a_styled_tooltip(page, studio):
    _author(page, studio)
    name = page.locator(".editor-domain .cm-line", has_text=":precondition (not (far ?b))").locator(".vslsp-ref")
    name.first.hover()
    tip = page.locator(".cm-tooltip .vslsp-hover")
    tip.wait_for()
    assert tip.inner_text() == "(far ?b - block)"
    assert page.locator(".editor-domain .vslsp-ref[title]").count() == 0  # no native title left


def test_completion_items_show_their_kind_and_declaration(page, studio):
    _author(page, studio)
    _cursor_in(page, ":precondition (not (far ?b))", len("ar ?b))"))
    page.keyboard.press("Control+Space")
    option = page.locator(".cm-tooltip-autocomplete li", has_text="far").first
    option.wait_for()
    assert option.locator(".cm-completionIcon-function").count() == 1
    assert "(far ?b - block)" in option.inner_text()


def test_definition_references_rename_and_outline(page, studio, studio_root):
    _author(page, studio)
    _cursor_in(page, ":precondition (not (far ?b))", len(" ?b))"))
    page.keyboard.press("F12")
    page.locator(".navigation", has_text="predicate (far ?b - block): pddl/domain.pddl:8:6").wait_for()
    page.locator(".editor-domain .cm-activeLine", has_text="(far ?b - block)").wait_for()
    _cursor_in(page, ":precondition (not (far ?b))", len(" ?b))"))
    page.keyboard.press("Shift+F12")
    page.locator(".references-title", has_text="15 places name predicate far").wait_for()
    assert page.locator(".reference").count() == 15
    assert [t.strip() for t in page.locator(".outline-domain").all_inner_texts()][:3] == [
        "domain vsl-sp",
        "type block",
        "predicate far",
    ]
    _cursor_in(page, ":precondition (not (far ?b))", len(" ?b))"))
    page.locator("#rename").click()
    page.locator(".rename-to input").fill("distant")
    page.locator("#rename-ok").click()
    page.locator(".editor-problem .cm-line", has_text="(distant orange)").first.wait_for()
    page.locator(".no-diagnostics").wait_for()
    shown = page.locator(".editor-domain .cm-content").inner_text()
    assert "(not (distant ?b))" in shown and "(not (far ?b))" not in shown  # a comment's "(far ?b)" stays
    assert page.locator(".unsaved-domain").is_visible() and page.locator(".unsaved-problem").is_visible()
    assert "(far" in (studio_root / "pddl/domain.pddl").read_text()  # nothing written before Save


def test_save_asks_before_writing_over_a_file_changed_on_disk(page, studio, studio_root):
    _author(page, studio)
    _cursor_in(page, ":precondition (not (far ?b))", 0)
    page.keyboard.type(" ; mine")
    page.locator(".unsaved-domain").wait_for()
    domain = studio_root / "pddl/domain.pddl"
    domain.write_text(domain.read_text() + "; theirs\n")
    page.locator(".disk-notice", has_text="changed on disk since opened: pddl/domain.pddl").wait_for()
    page.locator("#save").click()
    page.locator(".save-risk", has_text="pddl/domain.pddl changed on disk").wait_for()
    page.locator("#keep").click()
    assert "; theirs" in domain.read_text() and "; mine" not in domain.read_text()
    page.locator("#save").click()
    page.locator("#overwrite").click()
    page.locator(".unsaved-domain").wait_for(state="hidden")
    assert "; mine" in domain.read_text()
    page.wait_for_function("window.vslspUnsaved === false")  # set by the page once the save is answered


def test_a_ground_address_naming_no_image_says_so(page, studio):
    page.goto(f"{studio}/ground?pre=nowhere.png&post=examples/grounding/post.png")
    page.locator(".page-error", has_text="not an image or predicates file under the root: pre nowhere.png").wait_for()
    page.locator("#ground").wait_for()  # the page works on
