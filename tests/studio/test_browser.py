"""The studio's pages driven in a real headless Chromium (Debian's /usr/bin/chromium, through
Playwright): the author page's live diagnostics, plan timeline and violations, the ground page's
atoms, an experiment run watched to its report. The studio runs as ``vslsp studio`` would."""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers.studio import CHROMIUM, TOKEN

pytestmark = pytest.mark.skipif(not Path(CHROMIUM).exists(), reason=f"no {CHROMIUM} (apt-get install chromium)")
pytest.importorskip("playwright.sync_api", reason="pip install playwright")


def _author(page, studio: str) -> None:
    page.goto(f"{studio}/author?domain=pddl/domain.pddl&problem=pddl/pull-in-order.pddl")
    page.locator(".editor-domain .cm-content").wait_for()
    page.locator(".no-diagnostics").wait_for()


def test_a_typo_shows_its_diagnostic_on_its_line_and_goes_when_fixed(page, studio, tmp_path):
    _author(page, studio)
    line = page.locator(".editor-domain .cm-line", has_text=":precondition (not (far ?b))")
    line.click()
    page.keyboard.press("End")
    for _ in range(len(" ?b))")):
        page.keyboard.press("ArrowLeft")
    page.keyboard.type("s")  # (not (fars ?b)): an unknown predicate
    flagged = page.locator(".editor-domain .cm-line.vslsp-line-error")
    flagged.wait_for()
    assert "(fars ?b)" in flagged.inner_text() and "unknown predicate 'fars'" in flagged.inner_text()
    page.locator(".diagnostic-error", has_text="pddl/domain.pddl:12:").wait_for()
    page.screenshot(path=str(tmp_path / "studio-author.png"))  # README's docs/images/studio-author.png, copied once
    page.keyboard.press("Backspace")
    page.locator(".no-diagnostics").wait_for()
    assert page.locator(".editor-domain .cm-line.vslsp-line-error").count() == 0


def test_a_quick_fix_and_completion(page, studio):
    _author(page, studio)
    page.locator(".editor-domain .cm-line", has_text=":effect (far ?b))").first.click()
    page.keyboard.press("End")
    for _ in range(len(" ?b))")):
        page.keyboard.press("ArrowLeft")
    page.keyboard.type("x")
    page.locator(".quick-fix", has_text="change to 'far'").click()
    page.locator(".no-diagnostics").wait_for()
    page.locator(".editor-domain .cm-line", has_text=":effect (far ?b))").first.click()
    page.keyboard.press("End")
    for _ in range(len("ar ?b))")):
        page.keyboard.press("ArrowLeft")
    page.keyboard.press("F2")
    page.locator(".completion").first.wait_for()
    assert "far" in page.locator(".completion").all_inner_texts()


def test_ctrl_space_completes_the_name_at_the_cursor(page, studio):
    _author(page, studio)
    page.locator(".editor-domain .cm-line", has_text=":precondition (not (far ?b))").click()
    page.keyboard.press("End")
    for _ in range(len(" ?b))")):
        page.keyboard.press("ArrowLeft")
    page.keyboard.press("Backspace")
    page.keyboard.press("Backspace")  # (not (f ?b)): an unknown predicate
    page.locator(".diagnostic-error", has_text="unknown predicate 'f'").wait_for()
    # Until the page has added its completion source, Ctrl-Space offers CodeMirror's own words.
    page.wait_for_function("window.vslspCompletion && window.vslspCompletion.domain")
    page.keyboard.press("Control+Space")
    offered = page.locator(".cm-tooltip-autocomplete li .cm-completionLabel")
    offered.first.wait_for()
    assert "far" in offered.all_inner_texts()
    offered.filter(has_text="far").first.click()
    page.locator(".no-diagnostics").wait_for()
    assert page.locator(".editor-domain .cm-line", has_text=":precondition (not (far ?b))").count() == 1


def test_plan_shows_the_steps_and_the_timeline(page, studio):
    _author(page, studio)
    page.locator("#plan").click()
    page.locator(".plan-step").nth(2).wait_for()
    assert page.locator(".plan-step").all_inner_texts() == ["(pull orange)", "(pull green)", "(pull yellow)"]
    table = page.locator("table.timeline")
    assert table.locator("tr").count() == 5  # the header and s_0..s_3
    assert table.locator("td.kept").count() == 8 and table.locator("td.broken").count() == 0


def test_validate_marks_both_violations_on_steps_and_constraint_lines(page, studio):
    _author(page, studio)
    page.locator(".editor-plan .cm-content").click()
    page.keyboard.type("(pull yellow)\n(pull green)\n(pull orange)\n")
    page.locator("#validate").click()
    page.locator(".verdict-invalid").wait_for()
    assert page.locator(".violation").count() == 2
    marked = page.locator(".editor-problem .cm-line.vslsp-line-violation").all_inner_texts()
    assert len(marked) == 2 and all("sometime-before" in text for text in marked)
    steps = page.locator(".editor-plan .cm-line.vslsp-line-violation").all_inner_texts()
    assert steps == ["(pull yellow)", "(pull green)"]
    assert page.locator("table.timeline td.broken").count() == 5


def test_an_unsolvable_problem_shows_its_conflict_on_its_lines(page, studio):
    _author(page, studio)
    page.locator(".editor-problem .cm-line", has_text="(:constraints (and").click()
    page.keyboard.press("End")
    page.keyboard.type(" (always (far green))")  # the goal wants green near: no plan
    page.locator(".editor-problem .cm-line", has_text="(always (far green))").wait_for()
    page.locator("#plan").click()
    page.locator(".plan-error").wait_for()
    assert "no plan" in page.locator(".plan-error").inner_text(), page.locator(".diagnostics").inner_text()
    assert page.locator(".conflict-item").count() >= 2
    marked = page.locator(".editor-problem .cm-line.vslsp-line-conflict").all_inner_texts()
    assert any("(always (far green))" in text for text in marked)


def test_ground_the_example_pair_shows_the_atoms(page, studio):
    rel = "examples/grounding"
    page.goto(f"{studio}/ground?pre={rel}/pre.png&post={rel}/post.png&predicates={rel}/predicates.py")
    page.locator("#ground").click()
    page.locator(".atoms-post").wait_for()
    assert "right-half" in page.locator(".atoms-pre").inner_text() + page.locator(".atoms-post").inner_text()
    assert "moved:" in page.locator(".moved").inner_text()
    page.locator("img.overlay, .overlay img").first.wait_for()


@pytest.mark.slow
def test_start_a_run_watch_it_finish_and_open_its_report(page, studio):
    page.goto(f"{studio}/experiments")
    page.locator(".experiments-table").wait_for()
    assert "house-roof" in page.locator(".experiments-table").inner_text()
    page.locator("#start").click()  # house-roof, one trial: the fastest
    page.locator(".run-running, .run-done").first.wait_for()
    page.locator(".run-done").wait_for(timeout=300_000)
    assert "1/1 trials, 1 succeeded" in page.locator(".run-done").inner_text()
    page.locator(".report-link").click()
    page.locator(".summary-table").wait_for()
    images = page.locator(".report-image img")
    images.first.wait_for()
    assert images.count() >= 3
    page.wait_for_function("() => document.querySelector('.report-image img').naturalWidth > 0")  # drawn
    sources = page.evaluate("() => [...document.querySelectorAll('.report-image img')].map(i => i.src)")
    for source in sources:  # the ones below the fold load when scrolled to: each is served as a PNG
        answer = page.request.get(source)
        assert answer.ok and answer.body()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_dropped_image_is_uploaded_under_the_root_and_chosen(page, studio, studio_root):
    page.goto(f"{studio}/ground")
    page.locator("input[type=file]").first.set_input_files(str(studio_root / "examples/grounding/pre.png"))
    page.wait_for_function("() => document.querySelector('.pick-pre input').value === 'out/studio/uploads/pre.png'")
    assert (studio_root / "out/studio/uploads/pre.png").read_bytes() == (
        studio_root / "examples/grounding/pre.png"
    ).read_bytes()


def test_a_report_with_a_vsl3d_cloud_shows_it_in_3d(page, studio, studio_root):
    import json

    import numpy as np

    from vslsp.vsl3d.cloud import Frame
    from vslsp.vsl3d.vsl import CloudObservation

    folder = studio_root / "out" / "clouds"
    folder.mkdir(parents=True)
    (folder / "report.json").write_text(json.dumps({"experiment": "table-cleaning", "trials": 1}))
    grid = np.stack(np.meshgrid(np.linspace(0, 0.1, 20), np.linspace(0, 0.1, 20), [0.0, 0.05]), -1).reshape(-1, 3)
    CloudObservation(grid, Frame((0, 0, 0), (0.1, 0.1, 0.05)), np.zeros(3)).save(folder / "object.npz")
    page.goto(f"{studio}/reports/out/clouds")
    page.locator(".cloud-view canvas").wait_for()
    assert "800 points" in page.locator(".q-card", has_text="object.npz").inner_text()


@pytest.mark.token
def test_with_a_token_the_page_needs_it_and_works_with_it(page, studio):
    refused = page.goto(f"{studio}/author")
    assert refused is not None and refused.status == 401
    page.goto(f"{studio}/author?domain=pddl/domain.pddl&problem=pddl/pull-in-order.pddl&token={TOKEN}")
    page.locator(".no-diagnostics").wait_for()
    page.locator("#plan").click()  # the page's websocket carries the cookie the first visit set
    page.locator(".plan-step").nth(2).wait_for()
